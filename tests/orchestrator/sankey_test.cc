#include "orchestrator/report/sankey.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mtg::orchestrator {
namespace {

// A results database is data from anyone who shares a run folder: its causes and stages reach the
// report, the viewer (as innerHTML) and exported sites only as text, never as markup.
TEST(Sankey, LabelsAreTextNotMarkup) {
  const std::string evil = "<img src=x onerror=\"alert(1)\">&'";
  std::vector<SankeyFlow> flows;
  flows.push_back({"L1", "placed", evil, "failure"});
  flows.push_back({"L1", evil, "wrong_place", "failure"});
  const std::string svg = sankey_svg(sankey_graph(flows), kSankeyWidth, kSankeyHeight);
  EXPECT_EQ(svg.find("<img"), std::string::npos) << svg;
  EXPECT_EQ(svg.find("onerror=\""), std::string::npos) << svg;
  EXPECT_NE(svg.find("&lt;img src=x onerror=&quot;alert(1)&quot;&gt;&amp;&#39;"), std::string::npos) << svg;
}

}  // namespace
}  // namespace mtg::orchestrator
