#include "core/util/hash.h"

#include <array>

namespace mtg {

std::uint64_t fnv1a64(std::span<const std::uint8_t> bytes, std::uint64_t state) {
  for (const std::uint8_t b : bytes) {
    state ^= b;
    state *= 1099511628211ull;
  }
  return state;
}

std::uint64_t fnv1a64(std::string_view text, std::uint64_t state) {
  return fnv1a64(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), state);
}

std::string to_hex(std::uint64_t value) {
  static constexpr std::array<char, 16> kDigits = {'0', '1', '2', '3', '4', '5', '6', '7',
                                                   '8', '9', 'a', 'b', 'c', 'd', 'e', 'f'};
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i) {
    out[static_cast<size_t>(i)] = kDigits[value & 0xF];
    value >>= 4;
  }
  return out;
}

}  // namespace mtg
