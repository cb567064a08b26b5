#pragma once
// SHA-256 (OpenSSL) for identities others rely on: a recording's reference, a suite's digest.
// FNV-1a (hash.h) stays for content we produced ourselves and only compare with ourselves.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace mtg {

/// 64 lower-case hex digits. @throws mtg::Error when OpenSSL fails.
std::string sha256_hex(std::span<const std::uint8_t> bytes);
std::string sha256_hex(std::string_view text);

}  // namespace mtg
