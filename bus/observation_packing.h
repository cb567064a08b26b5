#pragma once
// How observations travel compactly (schema 7), and how whoever reads them gets them whole.
//
// An attempt's observations repeat themselves: the task text at every step, most of the offered
// actions (the "go to platform" list is the same at every step), most of the situation text, and
// the views of what did not change. On the bus and in recordings (observation_t, schema 7):
//   - a step's words are a change of the steps before: the task text only when it changed; the
//     situation text as copies from the step before's and the bytes that are new; the offered
//     actions as runs of the attempt's table of options, with only the options never offered
//     before in full (the first step's long list zstd-compressed);
//   - an image that an earlier observation of the attempt carried comes as a reference: the
//     image_t with nbytes == 0 and the earlier one's content_hash.
// Nothing a policy receives changes: the agent host (and every reader of recordings: the viewer,
// `mtg images`, exports) makes each observation whole with an ObservationReader before use.
//
// What may be referred to is only what the receiver must already have: words and images of an
// earlier step of the same attempt (the agent answered it, so it had it), or an earlier image of
// the same observation; never a resent copy of the same step, whose first copy may have been
// lost (a resent observation is the same message).

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "bus/episode_table.h"
#include "bus/finished_attempts.h"
#include "mtg/observation_t.hpp"

namespace mtg::bus {

/// What one observation may hold once whole, checked before anything of that size is made: a
/// packed observation of a few kilobytes could otherwise ask for gigabytes (runs of 32,767
/// options each, text copies of 32,767 bytes each, step after step). Real ones hold tens of
/// options, a few hundred bytes of text and a handful of images; the limits are far above that.
struct ObservationLimits {
  static constexpr std::size_t kActions = 16384;            // options offered at one step
  static constexpr std::size_t kTextBytes = 1u << 20;       // each of task text, situation text, hint
  static constexpr std::size_t kImages = 64;                // images of one observation
  static constexpr std::size_t kImageBytes = 32u << 20;     // one encoded image
  static constexpr int kImageSide = 16384;                  // pixels, width or height
  static constexpr std::size_t kOptionsTable = 65536;       // options an attempt offered in all
  static constexpr std::size_t kAttemptImageBytes = 512u << 20;  // images an attempt's reader keeps
};

/// zstd contexts for the first step's list of options; one per thread that uses it.
class WordsCodec {
 public:
  WordsCodec();
  ~WordsCodec();
  WordsCodec(const WordsCodec&) = delete;
  WordsCodec& operator=(const WordsCodec&) = delete;

  std::string compress(std::string_view bytes);
  /// @throws mtg::Error when the frame is damaged (its checksum) or claims more than `max` bytes.
  std::string decompress(std::string_view frame, std::size_t max);

 private:
  struct Contexts;
  std::unique_ptr<Contexts> z_;
};

/// The sender's side for one attempt (the scene-graph service keeps one per episode).
class WordsPacker {
 public:
  /// Packs obs's words as a change of the steps packed here before. Steps are packed in order,
  /// each once.
  void pack(mtg::observation_t& obs, WordsCodec& codec);

  /// The options an attempt has offered, each once, first offered first.
  struct Options {
    std::vector<mtg::action_option_t> items;
    std::unordered_map<std::string, int> index;  // key '\0' description -> its place in items
  };

 private:
  Options options_;
  std::string last_task_, last_text_;
  int last_step_ = -1;
};

/// The reader's side for one attempt: observations in the order they came, made whole.
class ObservationReader {
 public:
  /// `obs` with its words unpacked and every image by reference filled in from the earlier one.
  /// A second copy of a step read before reads as the first. An observation that is already
  /// whole (packed = false) passes as it is.
  /// @throws mtg::Error naming the step and what is missing, damaged, over ObservationLimits or
  /// inconsistent (an image whose bytes are not its content hash's) -- a lost or unrecorded
  /// observation, or a forged one; the attempt's later observations cannot be read either.
  mtg::observation_t whole(mtg::observation_t obs, WordsCodec& codec);

 private:
  struct Words {  // a step read: its texts, and its actions as runs of options_
    std::string task_text, text, hint;
    std::vector<int16_t> runs;
  };
  std::vector<mtg::action_option_t> options_;
  std::map<int, Words> steps_;                          // by step: for the next step, and a second copy
  int last_step_ = -1;                                  // the step read last
  std::map<std::string, std::vector<uint8_t>> images_;  // by content hash: the bytes
  std::size_t image_bytes_ = 0;                         // held in images_
};

/// Readers of a recording, where many attempts interleave: each observation made whole with its
/// attempt's reader, kept until the attempt's last observation.
class RecordedObservations {
 public:
  /// `packed` whole; nothing for a second copy of an attempt's last observation read before
  /// (its reader is gone; the first copy said all it holds).
  /// @throws mtg::Error as ObservationReader::whole does.
  std::optional<mtg::observation_t> whole(const mtg::observation_t& packed);

 private:
  WordsCodec codec_;
  std::map<std::tuple<std::string, std::int64_t, int>, ObservationReader> readers_;  // (run, episode, attempt)
  FinishedAttempts finished_;
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
