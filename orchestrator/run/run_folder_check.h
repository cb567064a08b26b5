#pragma once
// A run folder may sit in a shared, world-writable place (/tmp, a cluster file system), and run
// folders travel as tar files, which keep links. Anyone may then plant a link at a name the run
// writes (.lock, report.png, a dangling marks.sqlite) and have the run write what it names. Every
// writer refuses such a name itself (atomic_file.h); this check looks at every name a run, a
// resume, a report, a rejudge or a gather writes before any work starts, so a resume refuses in its
// first second rather than after its episodes (issue 55).

#include <filesystem>

namespace mtg::orchestrator {

/// @throws mtg::Error naming the first name in `dir` that a run writes and that is a symbolic
/// link, or is not a regular file (a folder it writes into: not a folder). Nothing in `dir` (or
/// no `dir`) is fine.
void check_run_folder(const std::filesystem::path& dir);

}  // namespace mtg::orchestrator
