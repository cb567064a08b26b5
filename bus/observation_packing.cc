#include "bus/observation_packing.h"

#include <zstd.h>

#include <set>
#include <utility>

#include "core/util/error.h"
#include "mtg/observation_words_t.hpp"

namespace mtg::bus {
namespace {

// Level 1: of zstd 1/3/6 and zlib 1/3/6 with the previous step as dictionary, the fastest and,
// on recorded apt_1 observations, as small as any (docs/bus.md, "Packed observations").
constexpr int kLevel = 1;
// Words of one observation are kilobytes; anything claiming more is damage, not words.
constexpr unsigned long long kMaxWords = 64ull << 20;

void check(std::size_t code, const char* what) {
  if (ZSTD_isError(code) != 0) throw Error(std::string(what) + ": " + ZSTD_getErrorName(code));
}

std::string step_name(const mtg::observation_t& obs) {
  return "the observation of step " + std::to_string(obs.step) + " (episode " +
         std::to_string(obs.header.episode_id) + ", attempt " + std::to_string(obs.header.attempt) + ")";
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
  check(ZSTD_CCtx_setParameter(z_->c, ZSTD_c_compressionLevel, kLevel), "zstd level");
  // The checksum covers the words unpacked, so a damaged frame or a wrong prefix is an error,
  // never other words.
  check(ZSTD_CCtx_setParameter(z_->c, ZSTD_c_checksumFlag, 1), "zstd checksum");
}

WordsCodec::~WordsCodec() = default;

std::string WordsCodec::pack(std::string_view words, std::string_view prefix) {
  std::string out(ZSTD_compressBound(words.size()), '\0');
  // A prefix holds for the next frame only.
  if (!prefix.empty()) check(ZSTD_CCtx_refPrefix(z_->c, prefix.data(), prefix.size()), "zstd prefix");
  const std::size_t n = ZSTD_compress2(z_->c, out.data(), out.size(), words.data(), words.size());
  check(n, "packing an observation's words");
  out.resize(n);
  return out;
}

std::string WordsCodec::unpack(std::string_view packed, std::string_view prefix) {
  const unsigned long long size = ZSTD_getFrameContentSize(packed.data(), packed.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > kMaxWords) {
    throw Error("packed words are not a zstd frame of known size");
  }
  std::string out(static_cast<std::size_t>(size), '\0');
  if (!prefix.empty()) check(ZSTD_DCtx_refPrefix(z_->d, prefix.data(), prefix.size()), "zstd prefix");
  const std::size_t n = ZSTD_decompressDCtx(z_->d, out.data(), out.size(), packed.data(), packed.size());
  // A failed frame leaves the prefix set: drop it, so the next frame starts clean.
  ZSTD_DCtx_reset(z_->d, ZSTD_reset_session_only);
  check(n, "unpacking an observation's words");
  if (n != out.size()) throw Error("packed words hold " + std::to_string(n) + " bytes, not " + std::to_string(size));
  return out;
}

std::string encode_words(const mtg::observation_t& obs) {
  mtg::observation_words_t w{};
  w.task_text = obs.task_text;
  w.text = obs.text;
  w.hint = obs.hint;
  w.actions = obs.actions;
  w.n_actions = static_cast<int32_t>(w.actions.size());
  std::string out(static_cast<std::size_t>(w.getEncodedSize()), '\0');
  if (w.encode(out.data(), 0, static_cast<int>(out.size())) < 0) throw InternalError("observation words do not encode");
  return out;
}

void WordsPacker::pack(mtg::observation_t& obs, WordsCodec& codec) {
  std::string words = encode_words(obs);
  const bool based = last_step_ >= 0 && last_step_ < obs.step;
  const std::string packed = codec.pack(words, based ? std::string_view(last_words_) : std::string_view());
  obs.packed_base = based ? last_step_ : -1;
  obs.packed.assign(packed.begin(), packed.end());
  obs.n_packed = static_cast<int32_t>(obs.packed.size());
  obs.task_text.clear();
  obs.text.clear();
  obs.hint.clear();
  obs.actions.clear();
  obs.n_actions = 0;
  last_words_ = std::move(words);
  last_step_ = obs.step;
}

mtg::observation_t ObservationReader::whole(const mtg::observation_t& obs, WordsCodec& codec) {
  mtg::observation_t out = obs;
  if (obs.n_packed > 0) {
    std::string_view prefix;
    if (obs.packed_base >= 0) {
      const auto base = words_.find(obs.packed_base);
      if (base == words_.end()) {
        throw Error(step_name(obs) + " refers to the words of step " + std::to_string(obs.packed_base) +
                    ", which did not come before it");
      }
      prefix = base->second;
    }
    std::string words;
    try {
      words = codec.unpack(std::string_view(reinterpret_cast<const char*>(obs.packed.data()), obs.packed.size()), prefix);
    } catch (const Error& e) {
      throw Error(step_name(obs) + ": " + e.what());
    }
    mtg::observation_words_t w{};
    if (w.decode(words.data(), 0, static_cast<int>(words.size())) != static_cast<int>(words.size())) {
      throw Error(step_name(obs) + ": its packed words do not decode");
    }
    out.task_text = std::move(w.task_text);
    out.text = std::move(w.text);
    out.hint = std::move(w.hint);
    out.actions = std::move(w.actions);
    out.n_actions = static_cast<int32_t>(out.actions.size());
    out.packed.clear();
    out.n_packed = 0;
    out.packed_base = -1;
    words_.emplace(obs.step, std::move(words));
  } else {
    words_.emplace(obs.step, encode_words(obs));
  }
  for (std::size_t i = 0; i < out.images.size(); ++i) {
    mtg::image_t& img = out.images[i];
    if (img.nbytes > 0) {
      images_.emplace(img.content_hash, img.data);
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
  return out;
}

mtg::observation_t RecordedObservations::whole(const mtg::observation_t& packed) {
  const auto key = std::make_tuple(packed.header.run_id, packed.header.episode_id, packed.header.attempt);
  mtg::observation_t obs = readers_[key].whole(packed, codec_);
  if (obs.done) readers_.erase(key);
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
