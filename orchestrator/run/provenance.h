#pragma once
// What made a run, so a result can say where it came from (docs/runtime.md, "Provenance"):
//  - plan.json's "provenance", written once when the run is planned: mtg version and git
//    revision, the command line, the host and time it was planned, the task set (file, config
//    hash, size), each scene's dataset digest, and the model settings of a run with model agents;
//  - sessions.jsonl, one line when an `mtg run` on the folder starts and one when it ends (a
//    resumed run has several; a killed one lacks its end): times, host, revision, command, and
//    at the end how many episodes it finished and how it ended.
// Wall-clock times here are records, never inputs: nothing reads them to decide anything.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/scene/dataset_fingerprint.h"

namespace mtg::orchestrator {

struct ProvenanceInputs {
  std::vector<std::string> command;  // argv, as given
  std::filesystem::path tasks_db;
  std::map<std::string, scene::DatasetFingerprint> dataset;  // of the scenes the plan runs
  nlohmann::json model_settings;  // the model adapters' settings (VlmSettings::provenance_json); null without one
};

nlohmann::json make_provenance(const ProvenanceInputs& inputs);

/// What a plan's task ids mean, from its provenance: the task set's config hash and the digests
/// of the scenes' dataset files ("config 1f2e…, apt_0 9a8b…"); "" for a plan from before
/// provenance.
std::string task_set_identity(const nlohmann::json& provenance);

/// Now, as "2026-11-28T10:58:03Z".
std::string utc_now();

/// Appends one JSON line to <run_dir>/sessions.jsonl (created if absent).
/// @throws mtg::Error when the file cannot be written.
void append_session(const std::filesystem::path& run_dir, const nlohmann::json& entry);

/// Every line of <run_dir>/sessions.jsonl that parses (a torn last line is skipped); [] without it.
nlohmann::json read_sessions(const std::filesystem::path& run_dir);

}  // namespace mtg::orchestrator
