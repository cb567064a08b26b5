#pragma once
// Seeded randomness with results that do not depend on the standard library: std::
// distributions differ between implementations, so we draw integers ourselves.

#include <cstdint>
#include <utility>
#include <vector>

namespace mtg {

/// Mixes two values into a new seed (SplitMix64 finaliser), e.g. (run seed, episode id).
std::uint64_t derive_seed(std::uint64_t a, std::uint64_t b);

/// xoshiro256** seeded through SplitMix64. Value type: copy it to fork a stream.
class Rng {
 public:
  explicit Rng(std::uint64_t seed);

  std::uint64_t next_u64();
  /// Uniform in [0, n), unbiased (Lemire's multiply-and-reject). Requires n > 0.
  std::uint64_t uniform_index(std::uint64_t n);
  /// Uniform in [0, 1).
  double uniform01();

  template <class T>
  void shuffle(std::vector<T>& values) {
    for (std::size_t i = values.size(); i > 1; --i) {
      std::swap(values[i - 1], values[uniform_index(i)]);
    }
  }

 private:
  std::uint64_t s_[4];
};

}  // namespace mtg
