#include "orchestrator/remote/gather.h"

#include <chrono>
#include <map>
#include <optional>

#include "bus/authenticator.h"
#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "bus/process/identity.h"
#include "bus/recording_ref.h"
#include "core/store/sqlite.h"
#include "core/util/file_bytes.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "mtg/record_chunk_t.hpp"
#include "mtg/recording_request_t.hpp"
#include "orchestrator/remote/episode_log.h"
#include "orchestrator/remote/merge_recordings.h"
#include "orchestrator/run/run_lock.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::orchestrator::remote {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Where the first folder of `from` holds a copy of `name` (a worker's --dir keeps it under
// <run id>/episodes/; a copy may be flat).
std::optional<fs::path> find_copy(const std::vector<fs::path>& from, const std::string& run_id, const std::string& name) {
  for (const fs::path& dir : from) {
    for (const fs::path& candidate : {dir / run_id / "episodes" / name, dir / "episodes" / name, dir / name}) {
      if (fs::is_regular_file(candidate)) return candidate;
    }
  }
  return std::nullopt;
}

// The key of the run's shared bus: the one given, $MTG_BUS_KEY, else the run folder's (a Slurm run).
std::string bus_key_for(const GatherOptions& o) {
  if (!o.bus_key.empty()) return o.bus_key;
  if (const char* env = std::getenv("MTG_BUS_KEY"); env != nullptr && *env != '\0') return env;
  if (fs::exists(o.run / "bus.key")) return (o.run / "bus.key").string();
  throw Error("mtg gather: the run's bus key is needed to ask the workers (--bus-key or $MTG_BUS_KEY); or give "
              "--from folders and --no-bus");
}

}  // namespace

GatherReport gather_recordings(const GatherOptions& o) {
  const fs::path run = fs::absolute(o.run).lexically_normal();
  if (!fs::exists(run / "plan.json")) throw Error(run.string() + ": no run folder (no plan.json)");
  const RunPlan plan = load_plan(run);
  const RunLock lock(run, "mtg gather");  // nothing else writes results.sqlite meanwhile
  GatherReport report;

  std::map<std::pair<std::int64_t, int>, bus::RecordingRef> wanted;  // (episode, attempt) -> ref
  for (const bus::RecordingRef& ref : bus::read_recording_refs(run / "results.sqlite")) {
    const fs::path here = episode_log_path(run, ref.episode, ref.attempt);
    const fs::path file = bus::resolve(ref, run);
    if (file == here && bus::check_recording(here, ref).empty()) {
      ++report.already;
      continue;
    }
    wanted[{ref.episode.value(), ref.attempt}] = ref;
  }
  store::Database db(run / "results.sqlite", store::Database::Mode::kReadWrite);
  // A recording whose bytes are the referenced ones goes to the run folder, and its reference
  // names the copy from then on.
  const auto keep = [&](const bus::RecordingRef& ref, const std::vector<std::uint8_t>& bytes) {
    if (static_cast<std::int64_t>(bytes.size()) != ref.bytes || bus::sha256_hex(bytes) != ref.sha256) return false;
    bus::RecordingRef moved = ref;
    moved.location = store_episode_log(run, ref.episode, ref.attempt, bytes).lexically_relative(run).string();
    moved.shared = true;
    bus::store_recording_ref(db, moved);
    report.bytes += static_cast<std::int64_t>(bytes.size());
    return true;
  };

  // Read once, kept only if its bytes are the referenced ones.
  const auto keep_from = [&](const bus::RecordingRef& ref, const fs::path& source) {
    try {
      // Only the attempt's own file, never more than its stored size (issue 55).
      std::error_code ec;
      if (!bus::recording_misfit(source, ref).empty() || fs::file_size(source, ec) != static_cast<std::uintmax_t>(ref.bytes)) {
        return false;
      }
      return fs::is_regular_file(source) && keep(ref, read_file_bytes(source));
    } catch (const Error&) {
      return false;  // unreadable: looked for elsewhere
    }
  };
  // From the shared folder where it was written, or from a copy of a worker's folder.
  for (auto it = wanted.begin(); it != wanted.end();) {
    const bus::RecordingRef& ref = it->second;
    // A path kept on another host names nothing here (even where this machine has one like it).
    const bool readable_here = ref.shared || ref.host == process::host_name();
    bool kept = readable_here && keep_from(ref, bus::resolve(ref, run));
    if (!kept) {
      const auto copy = find_copy(o.from, plan.run_id, fs::path(ref.location).filename().string());
      kept = copy && keep_from(ref, *copy);
    }
    if (kept) {
      ++report.copied;
      it = wanted.erase(it);
    } else {
      ++it;
    }
  }

  if (!wanted.empty() && o.bus) {
    bus::Bus bus(o.bus_url.empty() ? plan.bus_url : o.bus_url);
    bus.authenticate(bus::shared_bus_authenticator(bus_key_for(o)));
    bus::HeaderStamper stamp(plan.run_id, process::sender_id("gather"));
    std::map<std::string, ChunkAssembly> arriving;  // by location
    std::map<std::string, std::pair<std::int64_t, int>> by_location;
    for (const auto& [key, ref] : wanted) by_location[ref.location] = key;
    auto last_news = Clock::now();
    bus.subscribe<mtg::record_chunk_t>(bus::kRecord, [&](const std::string&, const mtg::record_chunk_t& m) {
      if (m.header.run_id != plan.run_id) return;
      const auto where = by_location.find(m.lease_id);
      if (where == by_location.end()) return;
      const auto w = wanted.find(where->second);
      if (w == wanted.end()) return;
      ChunkAssembly& a = arriving[m.lease_id];
      try {
        a.add(m);
      } catch (const Error&) {
        a = ChunkAssembly();
        a.add(m);
      }
      if (!a.complete()) return;
      std::vector<std::uint8_t> bytes;
      try {
        bytes = a.bytes();
      } catch (const Error& e) {
        log::warn(e.what());
        arriving.erase(m.lease_id);
        return;
      }
      arriving.erase(m.lease_id);
      if (!keep(w->second, bytes)) {
        log::warn(m.lease_id + " from " + m.header.sender + " is not the recording referenced (size or SHA-256)");
        return;
      }
      ++report.received;
      last_news = Clock::now();
      wanted.erase(w);
    });
    log::info("asking the workers on " + bus.url() + " for " + std::to_string(wanted.size()) + " recording(s)");
    auto next_ask = Clock::now();
    while (!wanted.empty() && Clock::now() - last_news < std::chrono::duration<double>(o.wait_s)) {
      if (Clock::now() >= next_ask) {
        // Asked in batches that fit a datagram, each host for its own; again for what is missing.
        std::map<std::string, std::vector<const bus::RecordingRef*>> by_host;
        for (const auto& [key, ref] : wanted) by_host[ref.host].push_back(&ref);
        for (const auto& [host, refs] : by_host) {
          for (std::size_t at = 0; at < refs.size(); at += 64) {
            mtg::recording_request_t m{};
            m.header = stamp.next({}, 0, "gather");
            m.host = host;
            for (std::size_t i = at; i < std::min(refs.size(), at + 64); ++i) {
              m.locations.push_back(refs[i]->location);
              m.episode_ids.push_back(refs[i]->episode.value());
              m.attempts.push_back(refs[i]->attempt);
            }
            m.n_files = static_cast<std::int32_t>(m.locations.size());
            bus.publish(bus::kRecordRequest, m);
          }
        }
        next_ask = Clock::now() + std::chrono::seconds(3);
      }
      bus.handle_once(50);
    }
  }
  for (const auto& [key, ref] : wanted) {
    report.missing.push_back("episode " + to_string(ref.episode) + " (attempt " + std::to_string(ref.attempt) + "): " +
                             ref.location + (ref.shared ? " in the shared folder" : " on " + ref.host) +
                             " was not found" + (o.bus ? " (no worker sent it)" : "") +
                             (o.from.empty() ? "" : " nor in the --from folders"));
  }
  return report;
}

}  // namespace mtg::orchestrator::remote
