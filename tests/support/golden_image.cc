#include "tests/support/golden_image.h"

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace mtg::testing {
namespace fs = std::filesystem;

std::string compare_golden_image(const std::string& name, const cv::Mat& actual, ImageTolerance tolerance) {
  const fs::path golden = fs::path(MTG_SOURCE_DIR) / "tests" / "golden" / name;
  if (const char* update = std::getenv("MTG_UPDATE_GOLDEN"); update != nullptr && *update == '1') {
    fs::create_directories(golden.parent_path());
    cv::imwrite(golden.string(), actual);
    return "";
  }
  const cv::Mat expected = cv::imread(golden.string(), cv::IMREAD_COLOR);
  std::string flat = name;
  for (char& c : flat) c = c == '/' ? '_' : c;
  const fs::path out = fs::temp_directory_path() / ("actual_" + flat);
  if (expected.empty()) {
    cv::imwrite(out.string(), actual);
    return "no golden image " + golden.string() + "; actual written to " + out.string() +
           " (MTG_UPDATE_GOLDEN=1 creates it)";
  }
  if (expected.size() != actual.size()) {
    cv::imwrite(out.string(), actual);
    return "size differs from golden " + golden.string() + "; actual written to " + out.string();
  }
  cv::Mat diff;
  cv::absdiff(expected, actual, diff);
  std::vector<cv::Mat> channels;
  cv::split(diff, channels);
  cv::Mat worst = cv::max(cv::max(channels[0], channels[1]), channels[2]);
  const cv::Mat differs = worst > tolerance.channel;
  const double share = static_cast<double>(cv::countNonZero(differs)) / static_cast<double>(differs.total());
  if (share <= tolerance.max_share) return "";
  cv::Mat grey, view;
  cv::cvtColor(actual, grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(grey, view, cv::COLOR_GRAY2BGR);
  view.setTo(cv::Scalar(0, 0, 255), differs);
  const fs::path diff_file = fs::temp_directory_path() / ("diff_" + flat);
  cv::imwrite(out.string(), actual);
  cv::imwrite(diff_file.string(), view);
  std::ostringstream msg;
  msg << share * 100.0 << " % of pixels differ from golden " << golden.string() << " (allowed "
      << tolerance.max_share * 100.0 << " %); actual " << out.string() << ", diff " << diff_file.string()
      << " (MTG_UPDATE_GOLDEN=1 rewrites the golden after an intended change)";
  return msg.str();
}

}  // namespace mtg::testing
