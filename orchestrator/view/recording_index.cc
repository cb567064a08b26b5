#include "orchestrator/view/recording_index.h"

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <limits>
#include <span>

#include "bus/channels.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/observation_t.hpp"
#include "bus/header.h"
#include "bus/recording.h"
#include "core/util/error.h"

namespace mtg::orchestrator::view {

namespace fs = std::filesystem;

bool viewer_reads_channel(const std::string& channel) {
  using bus::EpisodeStream;
  return channel == bus::kEpisodeStart || channel == bus::kEpisodeTruth || channel == bus::kEpisodeResult ||
         channel == bus::kError || bus::is_episode_channel(channel, EpisodeStream::kObservation) ||
         bus::is_episode_channel(channel, EpisodeStream::kAction) ||
         bus::is_episode_channel(channel, EpisodeStream::kJudge);
}

RecordingIndex::RecordingIndex(fs::path run_dir) : run_dir_(std::move(run_dir)) {}

std::size_t RecordingIndex::refresh() {
  std::vector<bus::RecordingFile> logs;
  std::error_code ec;
  try {
    logs = bus::recording_files(run_dir_);
  } catch (const Error& e) {
    const std::lock_guard lock(mutex_);
    if (std::find(damage_.begin(), damage_.end(), e.what()) == damage_.end()) damage_.push_back(e.what());
  }

  const std::lock_guard lock(mutex_);
  for (const auto& log : logs) {
    if (std::any_of(files_.begin(), files_.end(), [&](const File& f) { return f.path == log.path; })) continue;
    if (log.ref) {
      // Read once, whole, if it is the recording referenced; named otherwise (and not read).
      const std::string problem = bus::check_recording(log.path, *log.ref);
      if (!problem.empty()) {
        damage_.push_back(problem);
        files_.push_back({log.path, std::numeric_limits<long>::max(), true});
        continue;
      }
    }
    files_.push_back({log.path, 0, log.ref.has_value()});
  }
  std::size_t added = 0;
  for (std::size_t i = 0; i < files_.size(); ++i) {
    File& file = files_[i];
    if (file.referenced && file.indexed_to > 0) continue;  // whole already (or refused)
    if (static_cast<long>(fs::file_size(file.path, ec)) <= file.indexed_to || ec) continue;
    // Read past damage (named once, damage()); a torn tail may be an event the recorder is still
    // writing: read again from its start next time.
    const bus::RecordingRead read = bus::read_recording(file.path, file.indexed_to, [&](const lcm::LogEvent& ev,
                                                                                      std::int64_t offset) {
      if (!viewer_reads_channel(ev.channel)) return;
      const auto header = bus::peek_header({static_cast<const std::uint8_t*>(ev.data), static_cast<std::size_t>(ev.datalen)});
      if (!header || !bus::episode_of(*header).valid()) return;
      places_[bus::episode_of(*header)].push_back({static_cast<std::uint32_t>(i), offset});
      ++added;
      std::string line;
      if (bus::is_episode_channel(ev.channel, bus::EpisodeStream::kAction)) {
        mtg::agent_action_t action;
        if (action.decode(ev.data, 0, ev.datalen) < 0) return;  // damage is the reader's to name
        line = action.parsed_key + " " + action.raw_reply + " " + action.error + "\n";
      } else if (bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation) &&
                 static_cast<std::size_t>(ev.datalen) <= kFeedbackObservationBytes) {
        mtg::observation_t observation;  // the feedback on the step before ("hint")
        if (observation.decode(ev.data, 0, ev.datalen) < 0 || observation.hint.empty()) return;
        line = observation.hint + "\n";
      }
      if (line.empty()) return;
      std::string& said = said_[bus::episode_of(*header)];
      if (said.size() >= kSaidPerEpisode) return;
      std::transform(line.begin(), line.end(), line.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      said.append(line, 0, kSaidPerEpisode - said.size());
    });
    file.indexed_to = static_cast<long>(read.end);
    torn_tails_.erase(i);
    for (const bus::RecordingDamage& d : read.damage) {
      if (d.at_end) {
        torn_tails_[i] = bus::describe(d);
      } else {
        damage_.push_back(bus::describe(d));
      }
    }
  }
  size_ += added;
  return added;
}

std::vector<RecordedMessage> RecordingIndex::messages_of(bus::EpisodeId episode_id) const {
  std::vector<Place> places;
  std::vector<fs::path> paths;
  {
    const std::lock_guard lock(mutex_);
    const auto it = places_.find(episode_id);
    if (it == places_.end()) return {};
    places = it->second;
    for (const File& f : files_) paths.push_back(f.path);
  }
  std::vector<RecordedMessage> out;
  out.reserve(places.size());
  std::size_t open_file = paths.size();
  std::unique_ptr<lcm::LogFile> log;
  for (const Place& p : places) {
    const std::size_t file = p.file;
    const long offset = static_cast<long>(p.offset);
    if (file != open_file) {
      log = std::make_unique<lcm::LogFile>(paths[file].string(), "r");
      if (!log->good()) throw Error(paths[file].string() + ": cannot read the recording");
      open_file = file;
    }
    std::fseek(log->getFilePtr(), offset, SEEK_SET);
    const lcm::LogEvent* ev = log->readNextEvent();
    if (ev == nullptr) throw Error(paths[file].string() + ": no event at byte " + std::to_string(offset));
    const auto* bytes = static_cast<const std::uint8_t*>(ev->data);
    out.push_back({ev->channel, std::vector<std::uint8_t>(bytes, bytes + ev->datalen)});
  }
  return out;
}

bool RecordingIndex::said_contains(bus::EpisodeId episode_id, const std::string& needle) const {
  const std::lock_guard lock(mutex_);
  const auto it = said_.find(episode_id);
  return it != said_.end() && it->second.find(needle) != std::string::npos;
}

std::string RecordingIndex::said_of(bus::EpisodeId episode_id) const {
  const std::lock_guard lock(mutex_);
  const auto it = said_.find(episode_id);
  return it == said_.end() ? std::string() : it->second;
}

std::vector<std::string> RecordingIndex::damage(bool finished) const {
  const std::lock_guard lock(mutex_);
  std::vector<std::string> all = damage_;
  if (finished) {
    for (const auto& [file, line] : torn_tails_) all.push_back(line);
  }
  return all;
}

std::size_t RecordingIndex::size() const {
  const std::lock_guard lock(mutex_);
  return size_;
}

}  // namespace mtg::orchestrator::view
