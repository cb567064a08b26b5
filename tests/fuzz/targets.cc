// The fuzz targets (targets.h): the bus's message decoders, packed observations, sealed
// answers, recordings, the task database's JSON, scene files and the reply parser.

#include "tests/fuzz/targets.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "bus/observation_packing.h"
#include "bus/recording.h"
#include "bus/truth_seal.h"
#include "core/episode/reply_parser.h"
#include "core/scene/dataset.h"
#include "core/scene/scene_loader.h"
#include "core/tasks/suite.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "mtg/action_list_t.hpp"
#include "mtg/action_option_t.hpp"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "mtg/error_event_t.hpp"
#include "mtg/header_t.hpp"
#include "mtg/heartbeat_t.hpp"
#include "mtg/image_t.hpp"
#include "mtg/judge_event_t.hpp"
#include "mtg/lease_renewal_t.hpp"
#include "mtg/lease_t.hpp"
#include "mtg/moved_object_t.hpp"
#include "mtg/object_placement_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/platform_offset_t.hpp"
#include "mtg/platform_order_t.hpp"
#include "mtg/rate_limit_t.hpp"
#include "mtg/record_chunk_t.hpp"
#include "mtg/recorded_t.hpp"
#include "mtg/recording_ref_t.hpp"
#include "mtg/recording_request_t.hpp"
#include "mtg/render_request_t.hpp"
#include "mtg/render_result_t.hpp"
#include "mtg/render_view_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/run_info_t.hpp"
#include "mtg/scene_request_t.hpp"
#include "mtg/scene_summary_t.hpp"
#include "mtg/state_update_t.hpp"
#include "mtg/task_set_request_t.hpp"
#include "mtg/task_set_summary_t.hpp"
#include "mtg/task_t.hpp"
#include "mtg/world_state_delta_t.hpp"

namespace mtg::fuzz {
namespace {

namespace fs = std::filesystem;

// A finding: what the target must never do, as the fuzzer (and the replay) sees a crash.
[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what);
  std::abort();
}

// A message that decodes must encode to the bytes it was read from and decode again the same:
// a decoder that takes what its encoder cannot write back would let a reader see another
// message than the one recorded.
template <class Msg>
void round_trip(const std::uint8_t* data, std::size_t size) {
  Msg m{};
  const int used = m.decode(data, 0, static_cast<int>(size));
  if (used < 0) return;
  const int n = m.getEncodedSize();
  if (n != used) finding("a decoded message encodes to another size than it was read from");
  std::vector<std::uint8_t> again(static_cast<std::size_t>(n));
  if (m.encode(again.data(), 0, n) != n) finding("a decoded message does not encode");
  if (std::memcmp(again.data(), data, static_cast<std::size_t>(n)) != 0) {
    finding("a decoded message encodes to other bytes than it was read from");
  }
}

using RoundTrip = void (*)(const std::uint8_t*, std::size_t);
const RoundTrip kMessages[] = {
      &round_trip<mtg::action_list_t>,
      &round_trip<mtg::action_option_t>,
      &round_trip<mtg::agent_action_t>,
      &round_trip<mtg::episode_result_t>,
      &round_trip<mtg::episode_start_t>,
      &round_trip<mtg::episode_truth_t>,
      &round_trip<mtg::error_event_t>,
      &round_trip<mtg::header_t>,
      &round_trip<mtg::heartbeat_t>,
      &round_trip<mtg::image_t>,
      &round_trip<mtg::judge_event_t>,
      &round_trip<mtg::lease_t>,
      &round_trip<mtg::moved_object_t>,
      &round_trip<mtg::object_placement_t>,
      &round_trip<mtg::observation_t>,
      &round_trip<mtg::platform_offset_t>,
      &round_trip<mtg::platform_order_t>,
      &round_trip<mtg::rate_limit_t>,
      &round_trip<mtg::record_chunk_t>,
      &round_trip<mtg::recorded_t>,
      &round_trip<mtg::render_request_t>,
      &round_trip<mtg::render_result_t>,
      &round_trip<mtg::render_view_t>,
      &round_trip<mtg::run_control_t>,
      &round_trip<mtg::run_info_t>,
      &round_trip<mtg::scene_request_t>,
      &round_trip<mtg::scene_summary_t>,
      &round_trip<mtg::state_update_t>,
      &round_trip<mtg::task_set_request_t>,
      &round_trip<mtg::task_set_summary_t>,
      &round_trip<mtg::task_t>,
      &round_trip<mtg::world_state_delta_t>,
      // Types added later go at the end: an input's first byte picks its type, and the corpus
      // holds inputs cut for the order above.
      &round_trip<mtg::lease_renewal_t>,
      &round_trip<mtg::recording_ref_t>,
      &round_trip<mtg::recording_request_t>};

const std::int64_t kHashes[] = {
      mtg::action_list_t::getHash(),
      mtg::action_option_t::getHash(),
      mtg::agent_action_t::getHash(),
      mtg::episode_result_t::getHash(),
      mtg::episode_start_t::getHash(),
      mtg::episode_truth_t::getHash(),
      mtg::error_event_t::getHash(),
      mtg::header_t::getHash(),
      mtg::heartbeat_t::getHash(),
      mtg::image_t::getHash(),
      mtg::judge_event_t::getHash(),
      mtg::lease_t::getHash(),
      mtg::moved_object_t::getHash(),
      mtg::object_placement_t::getHash(),
      mtg::observation_t::getHash(),
      mtg::platform_offset_t::getHash(),
      mtg::platform_order_t::getHash(),
      mtg::rate_limit_t::getHash(),
      mtg::record_chunk_t::getHash(),
      mtg::recorded_t::getHash(),
      mtg::render_request_t::getHash(),
      mtg::render_result_t::getHash(),
      mtg::render_view_t::getHash(),
      mtg::run_control_t::getHash(),
      mtg::run_info_t::getHash(),
      mtg::scene_request_t::getHash(),
      mtg::scene_summary_t::getHash(),
      mtg::state_update_t::getHash(),
      mtg::task_set_request_t::getHash(),
      mtg::task_set_summary_t::getHash(),
      mtg::task_t::getHash(),
      mtg::world_state_delta_t::getHash(),
      mtg::lease_renewal_t::getHash(),
      mtg::recording_ref_t::getHash(),
      mtg::recording_request_t::getHash()};
static_assert(sizeof(kHashes) / sizeof(kHashes[0]) == sizeof(kMessages) / sizeof(kMessages[0]),
              "one hash per message type, in the same order");

// First byte: the message type; the rest: its bytes (with the type's hash, as on the bus).
int lcm_messages(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  constexpr std::size_t n = sizeof(kMessages) / sizeof(kMessages[0]);
  kMessages[data[0] % n](data + 1, size - 1);
  return 0;
}

// Observations of attempts as a reader of a recording meets them: a sequence of messages, each
// a 2-byte big-endian length and an observation_t, made whole in order.
int packed_observations(const std::uint8_t* data, std::size_t size) {
  bus::RecordedObservations reader;
  std::size_t at = 0;
  while (at + 2 <= size) {
    const std::size_t n = std::min<std::size_t>((std::size_t{data[at]} << 8) | data[at + 1], size - at - 2);
    at += 2;
    mtg::observation_t obs{};
    if (obs.decode(data + at, 0, static_cast<int>(n)) >= 0) {
      try {
        const auto whole = reader.whole(obs);
        if (whole && (whole->actions.size() > bus::ObservationLimits::kActions ||
                      whole->text.size() > bus::ObservationLimits::kTextBytes)) {
          finding("an observation made whole is over its limits");
        }
      } catch (const Error&) {
      }
    }
    at += n;
  }
  return 0;
}

int sealed_answers(const std::uint8_t* data, std::size_t size) {
  mtg::episode_truth_t m{};
  if (m.decode(data, 0, static_cast<int>(size)) < 0) return 0;
  static const bus::TruthSeal seal = bus::TruthSeal::derived("fuzzing-secret-of-sixteen-bytes+", "run");
  try {
    (void)seal.open(m);
  } catch (const Error&) {
  }
  return 0;
}

// A scratch folder of this process, removed at exit.
const fs::path& scratch() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("mtg_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(fs::temp_directory_path() / ("mtg_fuzz_" + std::to_string(::getpid())), ec);
    });
    return d;
  }();
  return dir;
}

void write_file(const fs::path& file, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

int recording(const std::uint8_t* data, std::size_t size) {
  const fs::path log = scratch() / "bus-0.lcmlog";
  write_file(log, data, size);
  try {
    std::size_t events = 0;
    bus::read_recording(log, 0, [&](const lcm::LogEvent& ev, std::int64_t) {
      if (ev.datalen < 0) finding("an event of negative length");
      ++events;
    });
  } catch (const Error&) {
  }
  return 0;
}

int task_json(const std::uint8_t* data, std::size_t size) {
  const auto j = nlohmann::json::parse(data, data + size, nullptr, false);
  if (j.is_discarded()) return 0;
  try {
    (void)tasks::task_from_json(j);
  } catch (const Error&) {
  }
  return 0;
}

// A suite file (mtg-suite/1): refused in one line, or read whole with its digest holding.
int suite_file(const std::uint8_t* data, std::size_t size) {
  const fs::path file = scratch() / "suite.json";
  write_file(file, data, size);
  try {
    const tasks::Suite suite = tasks::read_suite(file);
    if (tasks::suite_digest(suite) != suite.digest) finding("a suite read although its digest does not hold");
  } catch (const Error&) {
  }
  return 0;
}

// A dataset of one table and one box; the input is its scene instance file.
int scene_file(const std::uint8_t* data, std::size_t size) {
  static const fs::path root = [] {
    const fs::path r = scratch() / "dataset";
    fs::create_directories(r / "configs/objects");
    fs::create_directories(r / "configs/scenes");
    fs::create_directories(r / "objects");
    std::ofstream(r / "objects/box.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                            "f 1 2 3 4\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    std::ofstream(r / "configs/objects/box.object_config.json") << R"({"render_asset": "../../objects/box.obj"})";
    std::ofstream(r / "configs/objects/table.object_config.json") << R"({"render_asset": "../../objects/box.obj"})";
    return r;
  }();
  write_file(root / "configs/scenes/fuzz.scene_instance.json", data, size);
  try {
    const scene::Dataset dataset = scene::index_dataset(root);
    scene::MeshCache cache;
    (void)scene::load_scene(dataset, "fuzz", cache);
  } catch (const Error&) {
  }
  return 0;
}

int reply_parser(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::string> offered = {"0", "-1", "l1", "l2", "l12", "o3", "o14", "startplace", "p7"};
  const auto parsed = episode::parse_reply(std::string_view(reinterpret_cast<const char*>(data), size), offered);
  if (parsed.ok && parsed.key.empty()) finding("a reply read as a key that is empty");
  if (parsed.offered && std::find(offered.begin(), offered.end(), parsed.key) == offered.end()) {
    finding("a reply read as an offered key that was not offered");
  }
  return 0;
}

}  // namespace

int message_type_of(std::int64_t hash) {
  for (std::size_t i = 0; i < sizeof(kHashes) / sizeof(kHashes[0]); ++i) {
    if (kHashes[i] == hash) return static_cast<int>(i);
  }
  return -1;
}

const std::vector<NamedTarget>& targets() {
  static const std::vector<NamedTarget> all = {
      {"lcm_messages", &lcm_messages},   {"packed_observations", &packed_observations},
      {"sealed_answers", &sealed_answers}, {"recording", &recording},
      {"task_json", &task_json},         {"scene_file", &scene_file},
      {"reply_parser", &reply_parser},   {"suite_file", &suite_file}};
  return all;
}

}  // namespace mtg::fuzz
