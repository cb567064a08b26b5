// libFuzzer's entry point for one target, chosen at build time (MTG_FUZZ_TARGET, its name).

#include <cstring>
#include <cstdlib>
#include <cstdio>

#include "tests/fuzz/targets.h"

namespace {

mtg::fuzz::Target chosen() {
  for (const auto& t : mtg::fuzz::targets()) {
    if (std::strcmp(t.name, MTG_FUZZ_TARGET) == 0) return t.run;
  }
  std::fprintf(stderr, "no fuzz target named %s\n", MTG_FUZZ_TARGET);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mtg::fuzz::Target target = chosen();
  return target(data, size);
}
