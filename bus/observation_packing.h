#pragma once
// How observations travel compactly (schema 7), and how whoever reads them gets them whole.
//
// An attempt's observations repeat themselves: the task text at every step, most of the offered
// actions (the "go to platform" list is the same at every step), most of the situation text, and
// the views of what did not change. On the bus and in recordings:
//   - the words (task text, situation, hint, actions) of a step are a zstd frame of their
//     observation_words_t, compressed with the previous step's words as its prefix (zstd's
//     "patch-from"): a step whose actions did not change costs tens of bytes, not kilobytes;
//   - an image that an earlier observation of the attempt carried comes as a reference: the
//     image_t with nbytes == 0 and the earlier one's content_hash.
// Nothing a policy receives changes: the agent host (and every reader of recordings: the viewer,
// `mtg images`, exports) makes each observation whole with an ObservationReader before use.
//
// What may be referred to is only what the receiver must already have: words of an earlier step
// of the same attempt (the agent answered it, so it had it), and images of an earlier step or
// earlier in the same observation (never of a resent copy of the same step, whose first copy may
// have been lost).

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "bus/episode_table.h"
#include "mtg/observation_t.hpp"

namespace mtg::bus {

/// zstd contexts for packing and unpacking words; one per thread that uses it (not thread-safe).
class WordsCodec {
 public:
  WordsCodec();
  ~WordsCodec();
  WordsCodec(const WordsCodec&) = delete;
  WordsCodec& operator=(const WordsCodec&) = delete;

  /// `words` compressed with `prefix` as the reference (empty: none). Deterministic.
  std::string pack(std::string_view words, std::string_view prefix);
  /// What `pack` was given. @throws mtg::Error when the frame is damaged or not of this prefix.
  std::string unpack(std::string_view packed, std::string_view prefix);

 private:
  struct Contexts;
  std::unique_ptr<Contexts> z_;
};

/// The encoding of an observation's words (what `packed` holds unpacked).
std::string encode_words(const mtg::observation_t& obs);

/// The sender's side for one attempt (the scene-graph service keeps one per episode).
class WordsPacker {
 public:
  /// Moves obs's words into obs.packed, against the words of the last step packed here.
  void pack(mtg::observation_t& obs, WordsCodec& codec);

 private:
  std::string last_words_;
  int last_step_ = -1;
};

/// The reader's side for one attempt: observations in the order they came, made whole.
class ObservationReader {
 public:
  /// `obs` with its words unpacked and every image by reference filled in from the earlier one.
  /// Remembers what later observations of the attempt may refer to. An observation that is
  /// already whole (n_packed == 0) passes as it is.
  /// @throws mtg::Error naming the step and what is missing (a lost or unrecorded observation).
  mtg::observation_t whole(const mtg::observation_t& obs, WordsCodec& codec);

 private:
  std::map<int, std::string> words_;                 // by step: the words as packed against
  std::map<std::string, std::vector<uint8_t>> images_;  // by content hash: the bytes
};

/// Readers of a recording, where many attempts interleave: each observation made whole with its
/// attempt's reader, kept until the attempt's last observation.
class RecordedObservations {
 public:
  /// `packed` whole. @throws mtg::Error as ObservationReader::whole does.
  mtg::observation_t whole(const mtg::observation_t& packed);

 private:
  WordsCodec codec_;
  std::map<std::tuple<std::string, std::int64_t, int>, ObservationReader> readers_;  // (run, episode, attempt)
};

/// The renderer's side: which images each attempt's observations carried, so that an unchanged
/// view is sent once per attempt. Bounded: an attempt is forgotten at its last observation, and
/// beyond `attempts` kept the lowest-numbered episode's first (its later views then go whole).
class SentImages {
 public:
  explicit SentImages(std::size_t attempts = 256) : sent_(attempts) {}
  /// Replaces each image of `obs` that an earlier step of its attempt (or an earlier image of
  /// `obs`) carried with a reference to it, and remembers the rest.
  void refer_to_earlier(mtg::observation_t& obs);
  /// The attempt's observation could not be sent: refer to nothing of it any more.
  void forget(const mtg::header_t& h) { sent_.erase(EpisodeTable<Attempt>::key_of(h)); }
  std::size_t attempts() const { return sent_.size(); }

 private:
  struct Attempt {
    int attempt = 0;                        // set by the table
    std::map<std::string, int> first_step;  // content hash -> the step that first carried it
  };
  EpisodeTable<Attempt> sent_;
};

}  // namespace mtg::bus
