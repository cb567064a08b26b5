#pragma once
// Which episode of a run a message is about. header_t carries it as a plain int64 (-1: none);
// inside the processes it is an EpisodeId, read from a header with episode_of() and written by
// HeaderStamper::next().

#include <cstdint>

#include "core/util/typed_id.h"
#include "mtg/header_t.hpp"

namespace mtg::bus {

/// The episode's number in its run (its row in results.sqlite); none for messages about no episode.
using EpisodeId = TypedId<struct EpisodeTag, std::int64_t>;

inline EpisodeId episode_of(const mtg::header_t& h) { return EpisodeId(h.episode_id); }

}  // namespace mtg::bus
