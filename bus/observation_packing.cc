#include "bus/observation_packing.h"

#include <zstd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <iterator>
#include <set>
#include <utility>

#include "core/util/error.h"
#include "core/util/hash.h"
#include "mtg/action_list_t.hpp"

namespace mtg::bus {
namespace {

// New options above this size (the first step's list: 3.4 kB for 62 options) travel compressed;
// later steps add a few short ones, which cost less as they are than a frame.
constexpr std::size_t kCompressAbove = 512;
// A list of options is kilobytes; a frame that claims more is damage, not options.
constexpr std::size_t kMaxOptions = 16u << 20;

void check(std::size_t code, const std::string& what) {
  if (ZSTD_isError(code) != 0) throw Error(what + ": " + ZSTD_getErrorName(code));
}

std::string step_name(const mtg::observation_t& obs) {
  return "the observation of step " + std::to_string(obs.step) + " (episode " +
         std::to_string(obs.header.episode_id) + ", attempt " + std::to_string(obs.header.attempt) + ")";
}

std::string option_key(const mtg::action_option_t& o) {
  std::string k;
  k.reserve(o.key.size() + 1 + o.description.size());
  k.append(o.key).push_back('\0');
  k.append(o.description);
  return k;
}

bool same(const mtg::action_option_t& a, const mtg::action_option_t& b) {
  return a.key == b.key && a.description == b.description;
}

}  // namespace

struct WordsCodec::Contexts {
  ZSTD_CCtx* c = ZSTD_createCCtx();
  ZSTD_DCtx* d = ZSTD_createDCtx();
  ~Contexts() {
    ZSTD_freeCCtx(c);
    ZSTD_freeDCtx(d);
  }
};

WordsCodec::WordsCodec() : z_(std::make_unique<Contexts>()) {
  if (z_->c == nullptr || z_->d == nullptr) throw Error("zstd: cannot allocate a context");
  check(ZSTD_CCtx_setParameter(z_->c, ZSTD_c_compressionLevel, 1), "zstd level");
  // A damaged frame is an error, never other options.
  check(ZSTD_CCtx_setParameter(z_->c, ZSTD_c_checksumFlag, 1), "zstd checksum");
}

WordsCodec::~WordsCodec() = default;

std::string WordsCodec::compress(std::string_view bytes) {
  std::string out(ZSTD_compressBound(bytes.size()), '\0');
  const std::size_t n = ZSTD_compress2(z_->c, out.data(), out.size(), bytes.data(), bytes.size());
  check(n, "compressing offered actions");
  out.resize(n);
  return out;
}

std::string WordsCodec::decompress(std::string_view frame, std::size_t max) {
  const unsigned long long size = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > max) {
    throw Error("compressed actions are not a zstd frame of a size up to " + std::to_string(max) + " bytes");
  }
  std::string out(static_cast<std::size_t>(size), '\0');
  const std::size_t n = ZSTD_decompressDCtx(z_->d, out.data(), out.size(), frame.data(), frame.size());
  check(n, "compressed actions");
  if (n != out.size()) throw Error("compressed actions hold " + std::to_string(n) + " bytes, not " + std::to_string(size));
  return out;
}

namespace {

// The places of `items` in `table`, appending those it lacks (moved from `items`). A list that
// repeats an earlier one in order costs one comparison per item: the guess is the place after
// the item before's.
std::vector<int> places_in(WordsPacker::Options& table, std::vector<mtg::action_option_t>& items) {
  std::vector<int> places;
  places.reserve(items.size());
  int guess = -1;
  for (mtg::action_option_t& item : items) {
    int at = -1;
    if (guess >= 0 && guess < static_cast<int>(table.items.size()) &&
        same(table.items[static_cast<std::size_t>(guess)], item)) {
      at = guess;
    } else {
      const auto [it, added] = table.index.emplace(option_key(item), static_cast<int>(table.items.size()));
      at = it->second;
      if (added) table.items.push_back(std::move(item));
    }
    places.push_back(at);
    guess = at + 1;
  }
  if (table.items.size() > 32767) throw Error("more than 32,767 different actions offered in one attempt");
  return places;
}

// Places as runs: pairs (first, count).
std::vector<int16_t> runs_of(const std::vector<int>& places) {
  std::vector<int16_t> runs;
  for (std::size_t i = 0; i < places.size();) {
    std::size_t j = i + 1;
    while (j < places.size() && places[j] == places[j - 1] + 1 && j - i < 32767) ++j;
    runs.push_back(static_cast<int16_t>(places[i]));
    runs.push_back(static_cast<int16_t>(j - i));
    i = j;
  }
  return runs;
}

// The options that runs give of `table`. @throws mtg::Error naming `what` when a run leaves it.
std::vector<mtg::action_option_t> resolve(const std::vector<int16_t>& runs, const std::vector<mtg::action_option_t>& table,
                                          const std::string& what) {
  if (runs.size() % 2 != 0) throw Error(what + " are not pairs");
  std::size_t total = 0;
  for (std::size_t i = 1; i < runs.size(); i += 2) total += static_cast<std::size_t>(std::max<int16_t>(runs[i], 0));
  if (total > ObservationLimits::kActions) {
    throw Error(what + " offer " + std::to_string(total) + " options (at most " +
                std::to_string(ObservationLimits::kActions) + ")");
  }
  std::vector<mtg::action_option_t> out;
  out.reserve(total);
  for (std::size_t i = 0; i < runs.size(); i += 2) {
    const int first = runs[i], count = runs[i + 1];
    if (first < 0 || count < 0 || static_cast<std::size_t>(first) + static_cast<std::size_t>(count) > table.size()) {
      throw Error(what + " refer to " + std::to_string(first) + ".." + std::to_string(first + count) + " of " +
                  std::to_string(table.size()) + " sent");
    }
    out.insert(out.end(), table.begin() + first, table.begin() + first + count);
  }
  return out;
}

// The text as copies from `base` and new bytes: ops are pairs (offset, length) of `base`, or
// (-1, length) of the returned literal bytes. Greedy, by 4-byte anchors (the last place of each
// in `base`): a situation text is a few hundred bytes, and what changes from step to step is a
// platform's name, a side, the step count.
std::string text_ops(const std::string& text, const std::string& base, std::vector<int16_t>& ops) {
  constexpr std::size_t kAnchor = 4, kMinCopy = 8, kMax = 32767;
  ops.clear();
  std::string literal;
  auto add_literal = [&](std::size_t from, std::size_t to) {
    for (std::size_t at = from; at < to; at += kMax) {
      const std::size_t n = std::min(kMax, to - at);
      ops.push_back(-1);
      ops.push_back(static_cast<int16_t>(n));
      literal.append(text, at, n);
    }
  };
  std::array<int16_t, 1024> anchors;
  anchors.fill(-1);
  auto hash = [](const char* p) {
    std::uint32_t v = 0;
    std::memcpy(&v, p, 4);
    return (v * 2654435761u) >> 22;  // 10 bits
  };
  const bool copies = base.size() >= kAnchor && base.size() <= kMax;
  if (copies) {
    for (std::size_t p = 0; p + kAnchor <= base.size(); ++p) anchors[hash(base.data() + p)] = static_cast<int16_t>(p);
  }
  std::size_t pending = 0, i = 0;
  while (copies && i + kAnchor <= text.size()) {
    const int16_t found = anchors[hash(text.data() + i)];
    if (found < 0 || std::memcmp(base.data() + found, text.data() + i, kAnchor) != 0) {
      ++i;
      continue;
    }
    std::size_t from = static_cast<std::size_t>(found), at = i, n = 0;
    while (at + n < text.size() && from + n < base.size() && text[at + n] == base[from + n]) ++n;
    while (at > pending && from > 0 && text[at - 1] == base[from - 1]) {
      --at;
      --from;
      ++n;
    }
    if (n < kMinCopy) {
      ++i;
      continue;
    }
    add_literal(pending, at);
    ops.push_back(static_cast<int16_t>(from));
    ops.push_back(static_cast<int16_t>(n));
    i = pending = at + n;
  }
  add_literal(pending, text.size());
  return literal;
}

}  // namespace

void WordsPacker::pack(mtg::observation_t& obs, WordsCodec& codec) {
  if (obs.step <= last_step_) {
    throw InternalError("step " + std::to_string(obs.step) + " packed after step " + std::to_string(last_step_));
  }
  obs.packed = true;
  obs.packed_base = last_step_;
  // The offered actions: runs of the table, and in full only those never offered before.
  const std::size_t known = options_.items.size();
  obs.runs = runs_of(places_in(options_, obs.actions));
  obs.n_runs = static_cast<int32_t>(obs.runs.size());
  mtg::action_list_t fresh{};
  fresh.actions.assign(options_.items.begin() + static_cast<std::ptrdiff_t>(known), options_.items.end());
  fresh.n_actions = static_cast<int32_t>(fresh.actions.size());
  obs.zactions.clear();
  obs.actions.clear();
  if (const auto size = static_cast<std::size_t>(fresh.getEncodedSize()); size > kCompressAbove) {
    std::string bytes(size, '\0');
    if (fresh.encode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0) throw InternalError("actions do not encode");
    const std::string frame = codec.compress(bytes);
    obs.zactions.assign(frame.begin(), frame.end());
  } else {
    obs.actions = std::move(fresh.actions);
  }
  obs.n_actions = static_cast<int32_t>(obs.actions.size());
  obs.n_zactions = static_cast<int32_t>(obs.zactions.size());
  // The situation text as copies from the step before's and what is new.
  std::string text = std::move(obs.text);
  obs.text = text_ops(text, last_text_, obs.text_ops);
  obs.n_text_ops = static_cast<int32_t>(obs.text_ops.size());
  last_text_ = std::move(text);
  // The task text only when it changed.
  obs.same_task = last_step_ >= 0 && obs.task_text == last_task_;
  if (obs.same_task) {
    obs.task_text.clear();
  } else {
    last_task_ = obs.task_text;
  }
  last_step_ = obs.step;
}

namespace {

std::string apply_text_ops(const mtg::observation_t& obs, const std::string& base) {
  if (obs.text_ops.size() % 2 != 0) throw Error(step_name(obs) + ": its text is not in pairs");
  std::size_t total = 0;
  for (std::size_t i = 1; i < obs.text_ops.size(); i += 2) {
    total += static_cast<std::size_t>(std::max<int16_t>(obs.text_ops[i], 0));
  }
  if (total > ObservationLimits::kTextBytes) {
    throw Error(step_name(obs) + ": its text would be " + std::to_string(total) + " bytes (at most " +
                std::to_string(ObservationLimits::kTextBytes) + ")");
  }
  std::string text;
  text.reserve(total);
  std::size_t literal = 0;
  for (std::size_t i = 0; i < obs.text_ops.size(); i += 2) {
    const int at = obs.text_ops[i], n = obs.text_ops[i + 1];
    const std::size_t from = at < 0 ? literal : static_cast<std::size_t>(at);
    const std::string& source = at < 0 ? obs.text : base;
    if (n < 0 || from + static_cast<std::size_t>(n) > source.size()) {
      throw Error(step_name(obs) + ": its text takes bytes " + std::to_string(from) + ".." +
                  std::to_string(from + static_cast<std::size_t>(std::max(n, 0))) + " of " +
                  std::to_string(source.size()) + (at < 0 ? " new" : " of the step before's"));
    }
    text.append(source, from, static_cast<std::size_t>(n));
    if (at < 0) literal += static_cast<std::size_t>(n);
  }
  if (literal != obs.text.size()) throw Error(step_name(obs) + ": its text leaves new bytes unused");
  return text;
}

void check_limits(const mtg::observation_t& obs) {
  auto over = [&](const std::string& what, std::size_t n, std::size_t limit) {
    if (n > limit) {
      throw Error(step_name(obs) + ": " + what + " " + std::to_string(n) + " (at most " + std::to_string(limit) + ")");
    }
  };
  over("its task text is bytes", obs.task_text.size(), ObservationLimits::kTextBytes);
  over("its situation text is bytes", obs.text.size(), ObservationLimits::kTextBytes);
  over("its feedback is bytes", obs.hint.size(), ObservationLimits::kTextBytes);
  over("its options number", obs.actions.size(), ObservationLimits::kActions);
  over("its images number", obs.images.size(), ObservationLimits::kImages);
  for (std::size_t i = 0; i < obs.images.size(); ++i) {
    const mtg::image_t& img = obs.images[i];
    const std::string name = "image " + std::to_string(i) + " (" + img.role + ")";
    over(name + " is bytes", img.data.size(), ObservationLimits::kImageBytes);
    if (img.nbytes > 0 && (img.width <= 0 || img.height <= 0 || img.width > ObservationLimits::kImageSide ||
                           img.height > ObservationLimits::kImageSide)) {
      throw Error(step_name(obs) + ": " + name + " claims " + std::to_string(img.width) + "x" +
                  std::to_string(img.height) + " pixels (1 to " + std::to_string(ObservationLimits::kImageSide) +
                  " a side)");
    }
    // The hash names the bytes everywhere after (references, the viewer's image URLs): bytes
    // that are not the hash's would be shown, or referred to, as another image.
    if (img.nbytes > 0 && img.content_hash != to_hex(fnv1a64(img.data))) {
      throw Error(step_name(obs) + ": " + name + " is not the image its content hash " + img.content_hash +
                  " names");
    }
  }
}

}  // namespace

mtg::observation_t ObservationReader::whole(mtg::observation_t obs, WordsCodec& codec) {
  check_limits(obs);
  if (obs.packed) {
    auto read = steps_.find(obs.step);
    if (read == steps_.end()) {
      if (obs.packed_base != last_step_) {
        throw Error(step_name(obs) + " changes the words of step " + std::to_string(obs.packed_base) + ", but " +
                    (last_step_ < 0 ? std::string("no step") : "step " + std::to_string(last_step_)) +
                    " came before it (an observation was lost, or is not in the recording)");
      }
      const Words* before = last_step_ >= 0 ? &steps_.at(last_step_) : nullptr;
      Words w;
      if (obs.same_task) {
        if (before == nullptr) throw Error(step_name(obs) + " repeats the task text of no step");
        w.task_text = before->task_text;
      } else {
        w.task_text = std::move(obs.task_text);
      }
      w.text = apply_text_ops(obs, before != nullptr ? before->text : std::string());
      w.hint = std::move(obs.hint);
      // What is new joins the table; the runs refer to it.
      mtg::action_list_t fresh{};
      if (obs.n_zactions > 0) {
        std::string bytes;
        try {
          bytes = codec.decompress(std::string_view(reinterpret_cast<const char*>(obs.zactions.data()),
                                                    obs.zactions.size()),
                                   kMaxOptions);
        } catch (const Error& e) {
          throw Error(step_name(obs) + ": " + e.what());
        }
        if (fresh.decode(bytes.data(), 0, static_cast<int>(bytes.size())) != static_cast<int>(bytes.size())) {
          throw Error(step_name(obs) + ": its compressed actions do not decode");
        }
      } else {
        fresh.actions = std::move(obs.actions);
      }
      if (options_.size() + fresh.actions.size() > ObservationLimits::kOptionsTable) {
        throw Error(step_name(obs) + ": the attempt's options would number " +
                    std::to_string(options_.size() + fresh.actions.size()) + " (at most " +
                    std::to_string(ObservationLimits::kOptionsTable) + ")");
      }
      std::move(fresh.actions.begin(), fresh.actions.end(), std::back_inserter(options_));
      w.runs = std::move(obs.runs);
      last_step_ = obs.step;
      read = steps_.emplace(obs.step, std::move(w)).first;  // earlier steps stay for a late second copy
    }
    const Words& w = read->second;
    obs.task_text = w.task_text;
    obs.text = w.text;
    obs.hint = w.hint;
    obs.actions = resolve(w.runs, options_, step_name(obs) + ": its runs of actions");
    obs.n_actions = static_cast<int32_t>(obs.actions.size());
    obs.packed = false;
    obs.packed_base = 0;
    obs.same_task = false;
    obs.text_ops.clear();
    obs.n_text_ops = 0;
    obs.runs.clear();
    obs.n_runs = 0;
    obs.zactions.clear();
    obs.n_zactions = 0;
  }
  for (std::size_t i = 0; i < obs.images.size(); ++i) {
    mtg::image_t& img = obs.images[i];
    if (img.nbytes > 0) {
      if (images_.count(img.content_hash) == 0) {
        image_bytes_ += img.data.size();
        if (image_bytes_ > ObservationLimits::kAttemptImageBytes) {
          throw Error(step_name(obs) + ": the attempt's images would hold " + std::to_string(image_bytes_) +
                      " bytes (at most " + std::to_string(ObservationLimits::kAttemptImageBytes) + ")");
        }
        images_.emplace(img.content_hash, img.data);
      }
      continue;
    }
    const auto earlier = images_.find(img.content_hash);
    if (img.content_hash.empty() || earlier == images_.end()) {
      throw Error(step_name(obs) + ": image " + std::to_string(i) + " (" + img.role + ") refers to image " +
                  img.content_hash + ", which no earlier observation of the attempt carried");
    }
    img.data = earlier->second;
    img.nbytes = static_cast<int32_t>(img.data.size());
  }
  return obs;
}

std::optional<mtg::observation_t> RecordedObservations::whole(const mtg::observation_t& packed) {
  const auto key = std::make_tuple(packed.header.run_id, packed.header.episode_id, packed.header.attempt);
  const FinishedAttempts::Key episode{packed.header.run_id, episode_of(packed.header)};
  auto reader = readers_.find(key);
  if (reader == readers_.end()) {
    const auto finished = finished_.last(episode);
    if (packed.done && finished && *finished == packed.header.attempt) return std::nullopt;
    reader = readers_.emplace(key, ObservationReader()).first;
  }
  mtg::observation_t obs = reader->second.whole(packed, codec_);
  if (obs.done) {
    readers_.erase(reader);
    finished_.add(episode, packed.header.attempt);
  }
  return obs;
}

void SentImages::refer_to_earlier(mtg::observation_t& obs) {
  Attempt* a = sent_.current(obs.header);
  if (a == nullptr) {
    if (!sent_.is_new_attempt(obs.header)) return;  // a late request of an older attempt: sent whole
    a = &sent_.start(obs.header, Attempt{});
  }
  std::set<std::string> here;  // carried whole earlier in this observation
  for (mtg::image_t& img : obs.images) {
    if (img.nbytes == 0 || img.content_hash.empty()) continue;
    const auto first = a->first_step.find(img.content_hash);
    if ((first != a->first_step.end() && first->second < obs.step) || here.count(img.content_hash) > 0) {
      img.data.clear();
      img.nbytes = 0;
      continue;
    }
    here.insert(img.content_hash);
    a->first_step.emplace(img.content_hash, obs.step);
  }
  if (obs.done) sent_.erase(EpisodeTable<Attempt>::key_of(obs.header));
}

}  // namespace mtg::bus
