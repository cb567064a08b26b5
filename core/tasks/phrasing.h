#pragma once
// Plain-English task texts. Several templates per goal type; which one a task gets is a seeded
// choice keyed by the task's goal, so it does not depend on generation order.

#include <cstdint>
#include <string>

#include "core/episode/goals.h"
#include "core/tasks/identify.h"

namespace mtg::tasks {

/// The instruction for an atomic goal. Objects are named by `words` (a noun, and for look-alikes
/// a relation that picks the instance out: identify.h); platforms by their full names, as the
/// action space lists them.
std::string atomic_text(const graph::SceneGraph& g, const episode::AtomicGoal& goal, const Wording& words,
                        std::uint64_t seed);

/// The hint an episode starts with when its text names look-alikes (the paper's "task-provided
/// descriptions"): which phrases pick them out and where, and how ordinals read; with images,
/// that close-ups of them follow in the same order. "" when there are none.
std::string lookalike_hint(const std::vector<Identification>& lookalikes, bool with_images);

/// "<first>, then <second>" (the paper's THEN connector), for any number of parts.
std::string sequence_text(const std::vector<std::string>& parts);

/// Replaces every `from` in `s` by `to` (a template's "{placeholder}" by its value).
void replace_all(std::string& s, const std::string& from, const std::string& to);

/// Naive English plural of a category name ("book" -> "books", "box" -> "boxes").
std::string plural(const std::string& noun);

}  // namespace mtg::tasks
