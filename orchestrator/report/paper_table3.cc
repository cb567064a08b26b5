#include "orchestrator/report/paper_table3.h"

#include <array>
#include <cmath>
#include <limits>

namespace mtg::orchestrator {
namespace {

struct PaperRow {
  const char* agent;
  std::array<double, 8> figures;  // IP, SR for Levels 1, 2, 3 and the average; NaN = not given
};

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// Transcribed from the paper's Table 3 (reference/paper-manitaskgen.txt).
constexpr std::array<PaperRow, 11> kRows = {{
    {"Human", {91, 65, 90, 61, 90, 60, 90, 62}},
    {"Random", {0.4, 0, 0.4, 0, 0.4, 0, 0.4, 0}},
    {"GPT-4o", {42, 13, 16, 4, 23, 2, 27, 6}},
    {"GPT-4o-mini", {16, 2, 7, 2, 12, 0, 12, 1}},
    {"Gemini-2.0-flash", {42, 12, 19, 4, 30, 1, 30, 6}},
    {"Gemini-1.5-flash", {47, 23, 18, 9, 29, 3, 31, 12}},
    {"Gemini-1.5-pro", {41, 16, 21, 8, 32, 2, 31, 9}},
    {"Claude-3.5-sonnet", {52, 16, 23, 8, 39, 3, 38, 9}},
    {"Claude-3.5-haiku", {36, 4, 16, 2, 26, 0, 26, 2}},
    {"Llama-3.2-11B-Vision-Ins", {1, 0, 2, 2, 2, 0, 2, 1}},
    {"Llama-3.2-90B-Vision-Ins", {kNone, 6, 9, 6, 20, 1, 18, 4}},
}};

nlohmann::json figure(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); }

}  // namespace

nlohmann::json paper_table3() {
  nlohmann::json rows = nlohmann::json::array();
  for (const PaperRow& r : kRows) {
    nlohmann::json row = {{"agent", r.agent}, {"ip", figure(r.figures[6])}, {"sr", figure(r.figures[7])}};
    for (int level = 1; level <= 3; ++level) {
      const auto i = static_cast<std::size_t>(2 * (level - 1));
      row["by_level"][std::to_string(level)] = {{"ip", figure(r.figures[i])}, {"sr", figure(r.figures[i + 1])}};
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace mtg::orchestrator
