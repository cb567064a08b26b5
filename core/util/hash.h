#pragma once
// Content hashes for ids, caches and determinism checks. FNV-1a is enough here: the hashes name
// content we produced ourselves; nothing relies on them against an adversary.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace mtg {

inline constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;

/// FNV-1a 64 of the bytes, continuing from `state` (chain calls to hash several pieces).
std::uint64_t fnv1a64(std::span<const std::uint8_t> bytes, std::uint64_t state = kFnvOffset);
std::uint64_t fnv1a64(std::string_view text, std::uint64_t state = kFnvOffset);

/// 16 lower-case hex digits.
std::string to_hex(std::uint64_t value);

}  // namespace mtg
