#pragma once
// Where each episode's messages lie in a run's recordings (bus-<k>.lcmlog, or the per-episode
// files a multi-host run kept where they were made: bus::recording_files), so the viewer reads
// one episode without decoding the whole run. The index grows as a live run's recorder appends:
// refresh() reads only the bytes added since the last call and stops before a half-written event;
// it reads on past damage inside a file and keeps a line for each damaged stretch.

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "bus/episode_id.h"

namespace mtg::orchestrator::view {

/// One recorded message, copied out of the log.
struct RecordedMessage {
  std::string channel;
  std::vector<std::uint8_t> data;
};

class RecordingIndex {
 public:
  explicit RecordingIndex(std::filesystem::path run_dir);

  /// Indexes what was appended to the recordings since the last call (new files included).
  /// Thread-safe; returns the number of messages added.
  std::size_t refresh();
  /// The episode's messages of the channels the viewer reads, in recording order.
  std::vector<RecordedMessage> messages_of(bus::EpisodeId episode_id) const;
  /// One line per damaged stretch found inside the recordings so far (bus::describe). With
  /// `finished` (no run writes the folder any more), a torn last event counts too: a live
  /// recorder may still be writing it, a finished one never will.
  std::vector<std::string> damage(bool finished) const;
  /// Messages indexed so far (all episodes).
  std::size_t size() const;
  /// Whether the episode's agent replied or answered, or was told, text containing `needle`
  /// (lower case): its keys, full replies and provider errors, and the feedback its observations
  /// carried, the first kSaidPerEpisode bytes of them.
  bool said_contains(bus::EpisodeId episode_id, const std::string& needle) const;
  /// The text said_contains searches ("" when the episode has none).
  std::string said_of(bus::EpisodeId episode_id) const;

  /// What is kept per episode for said_contains: a model's 15 replies fit; a run of 10,000
  /// episodes holds at most 640 MB only if every reply is long (built-in agents: a few bytes).
  static constexpr std::size_t kSaidPerEpisode = 64 * 1024;
  /// Observations are read for their feedback up to this size: every text-only step; a step
  /// carrying new images is larger and is not decoded (copying its images would slow the index
  /// of a rendered run tenfold), so its feedback is not searched.
  static constexpr std::size_t kFeedbackObservationBytes = 256 * 1024;

 private:
  struct File {
    std::filesystem::path path;
    long indexed_to = 0;  // byte offset of the first event not yet indexed
    bool referenced = false;  // a recording kept where it was made: checked once, read whole
  };
  // An event's place: which file (a run whose recordings stayed on the workers has one per
  // episode) and where in it.
  struct Place {
    std::uint32_t file = 0;
    std::int64_t offset = 0;
  };

  std::filesystem::path run_dir_;
  mutable std::mutex mutex_;
  std::vector<File> files_;
  std::map<bus::EpisodeId, std::vector<Place>> places_;
  std::map<bus::EpisodeId, std::string> said_;  // lower case, one line per answer
  std::size_t size_ = 0;
  std::vector<std::string> damage_;
  std::map<std::size_t, std::string> torn_tails_;  // by file: its torn last event, as read last
};

/// Whether the viewer keeps messages of this channel (episode streams, starts, truths, results,
/// errors; not renders, heartbeats or state updates).
bool viewer_reads_channel(const std::string& channel);

}  // namespace mtg::orchestrator::view
