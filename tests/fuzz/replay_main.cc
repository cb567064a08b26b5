// Replays files through the fuzz targets without libFuzzer (the ordinary build, ctest):
//   mtg_fuzz_replay TARGET FILE_OR_FOLDER...
// Exits 0 when every input was taken (accepted or refused with mtg::Error); a crash or another
// exception ends it as it would end the fuzzer, naming the input.
//   mtg_fuzz_replay --seeds RUN_DIR TASK_DB CORPUS_DIR
// writes seeds cut from a real run (its recording's messages, observations, answers and first
// events) and task set into CORPUS_DIR/<target>/ (how tests/fuzz/corpus was made).

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include <map>
#include <algorithm>

#include "bus/recording.h"
#include "core/tasks/task_db.h"
#include "mtg/observation_t.hpp"
#include "tests/fuzz/targets.h"

namespace {

namespace fs = std::filesystem;

void write(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << bytes;
}

int write_seeds(const fs::path& run, const fs::path& task_db, const fs::path& out) {
  std::map<int, int> per_type;
  std::map<std::tuple<std::string, std::int64_t, int>, std::string> attempts;  // observations, length-prefixed
  int truths = 0;
  mtg::bus::for_each_recorded_event(run, [&](const lcm::LogEvent& ev) {
    const auto* data = static_cast<const std::uint8_t*>(ev.data);
    const auto size = static_cast<std::size_t>(ev.datalen);
    if (size < 8 || size > 16384) return;
    std::int64_t hash = 0;
    for (int i = 0; i < 8; ++i) hash = (hash << 8) | data[i];
    const int type = mtg::fuzz::message_type_of(hash);
    if (type < 0) return;
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    if (per_type[type]++ < 2) {
      write(out / "lcm_messages" / (ev.channel + "-" + std::to_string(per_type[type])),
            std::string(1, static_cast<char>(type)) + bytes);
    }
    if (ev.channel == "MTG_EPISODE_TRUTH" && truths++ < 3) {
      write(out / "sealed_answers" / ("truth-" + std::to_string(truths)), bytes);
    }
    mtg::observation_t obs{};
    if (ev.channel == "MTG_OBS" && obs.decode(data, 0, static_cast<int>(size)) >= 0) {
      std::string& seq = attempts[{obs.header.run_id, obs.header.episode_id, obs.header.attempt}];
      if (seq.size() + size > 32768) return;
      seq.push_back(static_cast<char>(size >> 8));
      seq.push_back(static_cast<char>(size & 0xff));
      seq += bytes;
    }
  });
  int k = 0;
  for (const auto& [key, seq] : attempts) {
    if (k++ == 4) break;
    write(out / "packed_observations" / ("attempt-" + std::to_string(k)), seq);
  }
  // The recording's first events, cut at an event's end.
  const fs::path log = run / "bus-0.lcmlog";
  std::int64_t cut = 0;
  mtg::bus::read_recording(log, 0, [&](const lcm::LogEvent& ev, std::int64_t offset) {
    const std::int64_t end = offset + 24 + static_cast<std::int64_t>(ev.channel.size()) + ev.datalen;
    if (end <= 12000) cut = end;
  });
  std::ifstream in(log, std::ios::binary);
  std::string head(static_cast<std::size_t>(cut), '\0');
  in.read(head.data(), cut);
  write(out / "recording" / "head", head);
  int t = 0;
  mtg::tasks::for_each_task(task_db, {}, [&](mtg::tasks::Task task) {
    if (t < 8 && task.level == (t % 4) + 1) {
      write(out / "task_json" / ("L" + std::to_string(task.level) + "-" + std::to_string(t)),
            mtg::tasks::task_to_json(task).dump());
      ++t;
    }
  });
  std::printf("seeds written under %s\n", out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && std::strcmp(argv[1], "--seeds") == 0) return write_seeds(argv[2], argv[3], argv[4]);
  if (argc < 3) {
    std::fprintf(stderr, "usage: mtg_fuzz_replay TARGET FILE_OR_FOLDER...\n");
    return 2;
  }
  mtg::fuzz::Target target = nullptr;
  for (const auto& t : mtg::fuzz::targets()) {
    if (std::strcmp(t.name, argv[1]) == 0) target = t.run;
  }
  if (target == nullptr) {
    std::fprintf(stderr, "mtg_fuzz_replay: no target named %s\n", argv[1]);
    return 2;
  }
  std::vector<fs::path> inputs;
  for (int i = 2; i < argc; ++i) {
    const fs::path p(argv[i]);
    if (fs::is_directory(p)) {
      for (const auto& e : fs::directory_iterator(p)) {
        if (e.is_regular_file()) inputs.push_back(e.path());
      }
    } else if (fs::is_regular_file(p)) {
      inputs.push_back(p);
    } else {
      std::fprintf(stderr, "mtg_fuzz_replay: %s: no such file or folder\n", argv[i]);
      return 2;
    }
  }
  std::sort(inputs.begin(), inputs.end());
  if (inputs.empty()) {
    std::fprintf(stderr, "mtg_fuzz_replay: no inputs for %s\n", argv[1]);
    return 2;
  }
  for (const fs::path& input : inputs) {
    std::ifstream in(input, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::fprintf(stderr, "%s\n", input.c_str());  // the last name printed is the culprit of a crash
    target(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("%s: %zu inputs taken\n", argv[1], inputs.size());
  return 0;
}
