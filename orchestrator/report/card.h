#pragma once
// A run's result card (docs/runtime.md, "Result card"): what a paper or a model card quotes about
// a run, on one page: the suite it ran, its agents and model settings, SR and IP per level with
// their 95 % intervals and the paper's average, what the model calls cost, where the run came
// from, what a person excluded, and how to cite the benchmark, the tool and the suite.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace mtg::orchestrator {

/// The card of a report (make_report, with the run's marks applied) and the run's plan.json
/// (an object; {} without one). Keys: run, suite {id, declared, task_set}, agents,
/// model_settings, episodes, scored, errors, average_label, results {agent: {by_level,
/// paper_avg, all}}, cost {agent: usage} (model agents only), provenance {mtg_version,
/// git_revision, command, planned_at, host} or null, excluded [{episode, reason}], cite {paper,
/// tool, suite}.
nlohmann::json card_of(const nlohmann::json& report, const nlohmann::json& plan);

/// The card of a run folder. @throws mtg::Error naming the folder when it is not a run.
nlohmann::json make_card(const std::filesystem::path& run_dir);

/// The card as a Markdown page.
std::string card_markdown(const nlohmann::json& card);

/// Writes card.md and card.json into `run_dir`. @throws mtg::Error naming a file it cannot write.
void write_card(const std::filesystem::path& run_dir);

}  // namespace mtg::orchestrator
