#pragma once
// The fuzz targets (scripts/fuzz, docs/fuzzing.md): each takes arbitrary bytes and must neither
// crash, nor leak, nor throw anything but mtg::Error (the one-line refusal every reader gives
// bad input). Built with libFuzzer by scripts/fuzz (clang), and replayed over their seed corpus
// and past findings by ctest (FuzzCorpus.*) in the ordinary build.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mtg::fuzz {

using Target = int (*)(const std::uint8_t* data, std::size_t size);

struct NamedTarget {
  const char* name;
  Target run;
};

/// Every target, by the name of its corpus folder (tests/fuzz/corpus/<name>).
const std::vector<NamedTarget>& targets();

/// The first byte of an lcm_messages input for a message with this type hash (its first 8
/// bytes, big-endian); -1 for a type that is not ours.
int message_type_of(std::int64_t hash);

}  // namespace mtg::fuzz
