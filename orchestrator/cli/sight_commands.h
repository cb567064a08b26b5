#pragma once
// `mtg audit sights`: objects drawn from the platform views of some scenes, each written as the
// view with an arrow pointing at it, for people to say whether they can see and name it; `mtg
// audit sights report`: the visibility rule against their answers (docs/render.md, "Calibrated by
// eye").

#include <cstdint>
#include <string>
#include <vector>

namespace mtg::cli {

struct SightsDrawOptions {
  std::vector<std::string> scenes;
  std::string data_dir;
  std::string profile = "replica_cad";
  int count = 200;
  std::uint64_t seed = 0;
  std::string out;
  std::string key;        // where the answers go ("" = <out>-key.json beside the folder, not in it)
};

struct SightsReportOptions {
  std::string dir;        // holds sights.json and labels/*.json
  std::string key;        // the draw's key ("" = <dir>-key.json; draws before mtg-sights/2 hold it in sights.json)
  bool json = false;
};

int run_sights_draw(const SightsDrawOptions& options);
int run_sights_report(const SightsReportOptions& options);

}  // namespace mtg::cli
