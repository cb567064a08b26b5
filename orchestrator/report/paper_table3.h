#pragma once
// The paper's Table 3 (IP and SR per level, ten VLMs, a human and a random agent), shown next to
// a run's own rows for reference. Qwen2-VL-72B's row is left out: the paper's text of it is
// incomplete (three of eight figures).

#include <nlohmann/json.hpp>

namespace mtg::orchestrator {

/// [{"agent": "Human", "by_level": {"1": {"ip", "sr"}, "2": ..., "3": ...}, "ip", "sr"}, ...]
/// in the paper's order; a figure the paper omits is null.
nlohmann::json paper_table3();

}  // namespace mtg::orchestrator
