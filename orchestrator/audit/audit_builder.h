#pragma once
// Making an audit (docs/view.md, "mtg audit"): draws `per_level` tasks of each level, plays each
// one's oracle plan, and stores what the agent would see at the start and at each arrival (text,
// offered actions, images rendered as the renderer service renders them) with the questions to
// ask and their answers (audit_plan.h). Idempotent: a folder that holds this very audit is kept
// (with its answers); one that holds another is refused.

#include <cstdint>
#include <ostream>
#include <string>

namespace mtg::orchestrator::audit {

struct AuditOptions {
  std::string tasks;          // task database
  std::string scene;          // "" any
  int per_level = 10;
  std::uint64_t seed = 0;
  std::string out;            // the audit's folder
  std::string data_dir;       // dataset root ("" default search order)
  std::string profile = "replica_cad";
  int width = 640;
  int height = 480;
  bool names = false;         // name objects in the text, as runs without images do
  std::string lookalike_aid = "both";  // what the page gives of look-alikes (episode::LookalikeAid)
};

/// Returns the number of tasks the audit holds. @throws mtg::Error naming the file or option.
/// `redraw`: progress redraws one line (a terminal), else a line per tenth of the tasks (a log).
int build_audit(const AuditOptions& options, std::ostream& progress, bool redraw);

}  // namespace mtg::orchestrator::audit
