#pragma once
// Byte encodings the adapters need, through OpenSSL: base64 for images in request bodies and
// SHA-256 for response-cache keys (the keys cover image bytes, so a weak hash could collide).

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace mtg::vlm {

std::string base64_encode(std::span<const std::uint8_t> bytes);
/// 64 lower-case hex digits.
std::string sha256_hex(std::string_view text);

}  // namespace mtg::vlm
