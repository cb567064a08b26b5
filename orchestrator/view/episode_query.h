#pragma once
// Which episodes of a run the list shows, and in what order: the filters of the Sankey and the
// list's form, a free-text search over task ids, texts and replies, and a sort by any column
// (docs/view.md, "JSON API"). Pure functions over the results rows.

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator::view {

struct EpisodeFilter {
  std::optional<std::string> agent, scene, task, cause, stage, status;
  std::optional<int> level;
  std::optional<bool> success;

  bool matches(const EpisodeRow& row) const;
};

/// Task id -> task text (from the run's task database; empty when it cannot be read).
using TaskTexts = std::map<std::string, std::string>;

/// Whether the agent's replies or keys in an episode contain a (lower-case) needle: answered from
/// the recording's index (RecordingIndex::said_contains).
using SaidSearch = std::function<bool(bus::EpisodeId, const std::string& needle)>;

struct EpisodeQuery {
  EpisodeFilter filter;
  /// Case-insensitive; an episode matches when its task id, its task text or (with a SaidSearch)
  /// what its agent replied contains it, so a part of an id finds it.
  std::optional<std::string> text;
  std::string sort = "episode";  // one of sort_fields()
  bool descending = false;
};

/// The columns the list sorts by: episode, agent, level, scene, task, text, verdict, ip, stage,
/// cause, steps.
const std::vector<std::string>& sort_fields();

/// Positions in `rows` of the episodes `query` selects, in its order (ties by episode id).
/// @throws mtg::Error naming the field when `query.sort` is not one of sort_fields().
std::vector<std::size_t> select_episodes(const std::vector<EpisodeRow>& rows, const TaskTexts& texts,
                                         const EpisodeQuery& query, const SaidSearch& said = {});

}  // namespace mtg::orchestrator::view
