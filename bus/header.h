#pragma once
// Building and checking the common header (lcmtypes/header_t.lcm).

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <tuple>

#include "bus/episode_id.h"
#include "mtg/header_t.hpp"

namespace mtg::bus {

// 2: render requests carry the observation, and the renderer publishes it (images once); the
// per-episode streams have one channel each (MTG_OBS, not MTG_OBS_E<n>). 3: render requests
// carry the world state typed (world_state_delta_t), not as a JSON string. 4: images carry a
// caption, render views an object number and caption (close-ups numbered, zoomed views).
// 5: actions carry the model's request. 6: heartbeats, announcements and leases name sessions.
// 7: observations travel packed, their words against the step before and unchanged images by
// reference (bus/observation_packing.h). 8: leases go to each worker's own channel and are
// renewed together (lease_renewal_t); announcements say where recordings go (recording_ref_t).
// 9: episode starts say how look-alikes are told apart and how items are numbered, and world
// states carry the numbers kept (stable numbering, core/episode/world_state.h). 10: announcements
// say how the run's graphs read platforms (graph::PlatformRules).
inline constexpr std::int32_t kSchemaVersion = 10;

/// Whether a message with this header was written by a build of this schema (a message of another
/// schema may decode and still mean something else).
inline bool speaks_our_schema(const mtg::header_t& header) { return header.schema_version == kSchemaVersion; }
/// "<what> from <sender> has schema version N; this build speaks M".
std::string schema_mismatch(const mtg::header_t& header, const std::string& what);

/// Stamps outgoing headers: seq counts from 0 per (stream, episode, attempt), where a stream is
/// one kind of message (its channel family), so a receiver of that stream sees 0, 1, 2, ... and
/// can tell a lost message from one it was never meant to see. A process forgets an episode's
/// streams once the episode is over for it (forget_episode), so what it keeps does not grow with
/// the episodes of a long run (docs/runtime.md, "What each process keeps").
class HeaderStamper {
 public:
  HeaderStamper(std::string run_id, std::string sender)
      : run_id_(std::move(run_id)), sender_(std::move(sender)) {}

  mtg::header_t next(EpisodeId episode = {}, std::int32_t attempt = 0, const std::string& stream = "");
  /// A header with a given seq, for an answer numbered as its request (no stream kept).
  mtg::header_t with_seq(EpisodeId episode, std::int32_t attempt, std::int64_t seq) const;
  /// Forgets the streams of every attempt of `episode`: the next message about it starts at 0.
  void forget_episode(EpisodeId episode);
  /// Streams kept now.
  std::size_t streams() const { return next_seq_.size(); }
  const std::string& sender() const { return sender_; }
  const std::string& run_id() const { return run_id_; }
  void set_run_id(std::string run_id) { run_id_ = std::move(run_id); }

 private:
  std::string run_id_;
  std::string sender_;
  // (episode, attempt, stream) -> next seq: an episode's streams lie together for forget_episode.
  std::map<std::tuple<std::int64_t, std::int32_t, std::string>, std::int64_t> next_seq_;
};

/// The header_t every mtg message carries first (after LCM's 8-byte type fingerprint); nullopt
/// for bytes that do not start with one.
std::optional<mtg::header_t> peek_header(std::span<const std::uint8_t> message);

/// Checks incoming headers per (run, sender, episode, attempt) stream.
class SequenceTracker {
 public:
  enum class Verdict { kInOrder, kDuplicate, kGap };
  /// kGap when messages were skipped (the message is still accepted and the stream resyncs);
  /// kDuplicate for a seq already seen (or older).
  Verdict observe(const mtg::header_t& header);
  /// Forgets every stream of one episode of one run (another run's episode of that id stays).
  void forget_episode(const std::string& run_id, EpisodeId episode);

 private:
  std::map<std::tuple<std::string, std::string, std::int64_t, std::int32_t>, std::int64_t> last_seq_;
};

}  // namespace mtg::bus
