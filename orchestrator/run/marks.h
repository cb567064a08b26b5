#pragma once
// People's marks on a run's episodes (docs/view.md, "Marks"): a flag, tags, and exclusions from
// the statistics, each with who made it, when and why. They live in <run>/marks.sqlite, apart
// from results.sqlite, so no mark ever alters a verdict; every change is a new row (the audit
// trail), and an episode's marks are those rows replayed in order. An excluded episode leaves
// SR, IP and their intervals (the report says how many and why) and comes back when included
// again.

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "bus/episode_id.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {

enum class MarkAction { kFlag, kUnflag, kTag, kUntag, kExclude, kInclude };

/// "flag", "unflag", "tag", "untag", "exclude", "include".
const char* to_string(MarkAction a);
std::optional<MarkAction> mark_action_from_string(std::string_view name);

/// One change, as stored.
struct MarkEntry {
  bus::EpisodeId episode;
  MarkAction action = MarkAction::kFlag;
  std::string tag;     // kTag / kUntag: the tag
  std::string reason;  // why (required for kExclude and kInclude)
  std::string who;     // the person, as they named themselves
  std::string at;      // UTC time, a record only
};

/// What an episode carries now.
struct EpisodeMarks {
  bool flagged = false;
  std::set<std::string> tags;
  bool excluded = false;
  std::string exclusion_reason;
};

/// Limits of a person's input: a reason or name is a line, not a document.
inline constexpr std::size_t kMarkTextLimit = 500;

/// Checks a change before it is stored. @throws mtg::Error naming the field (no person, no
/// reason for an exclusion, a tag missing or too long, text beyond kMarkTextLimit).
void check_mark(const MarkEntry& entry);

/// Appends a change to <run_dir>/marks.sqlite (created on first use).
/// @throws mtg::Error from check_mark, or naming the file when it cannot be written.
void add_mark(const std::filesystem::path& run_dir, const MarkEntry& entry);

/// The trail, oldest first; [] when the run has no marks file.
std::vector<MarkEntry> read_marks(const std::filesystem::path& run_dir);

/// A number that grows with every change stored (0 without marks): readers cache on it.
std::int64_t marks_version(const std::filesystem::path& run_dir);

/// The trail replayed: each episode's marks now (episodes never marked are absent).
std::map<bus::EpisodeId, EpisodeMarks> current_marks(const std::vector<MarkEntry>& trail);

/// The rows the statistics count: `rows` without the episodes excluded now.
std::vector<EpisodeRow> without_excluded(const std::vector<EpisodeRow>& rows,
                                         const std::map<bus::EpisodeId, EpisodeMarks>& marks);

}  // namespace mtg::orchestrator
