// A command loads what its job needs (issue 56): `mtg --help` only the front's few libraries, and
// OpenCV's image codecs, with their 139 libraries, only when an image is decoded or encoded as
// JPEG (core/render/codec_module.h).
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "core/render/codec_module.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/process.h"
#include "tests/support/text_file.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;

// The libraries the dynamic loader opened for `argv` (LD_DEBUG=files), and its exit status.
std::pair<int, std::string> loaded_by(const std::vector<std::string>& argv, const fs::path& log) {
  ::setenv("LD_DEBUG", "files", 1);
  testing::ChildProcess p(argv, log.string());
  ::unsetenv("LD_DEBUG");
  const int status = p.wait(120000);
  return {status, testing::read_text(log)};
}

TEST(Startup, CommandsThatTouchNoImageLoadNoImageCodecs) {
  testing::FixtureDataset fx;
  (void)testing::two_tables(fx);
  const fs::path log = fx.root() / "ld.log";
  {
    // The front answers --help itself: the C++ runtime, the allocator, nothing of ours.
    const auto [status, text] = loaded_by({testing::bin("mtg"), "--help"}, log);
    EXPECT_EQ(status, 0) << text;
    EXPECT_NE(text.find("libjemalloc"), std::string::npos) << "LD_DEBUG did not report the loads";
    std::set<std::string> files;
    for (std::size_t at = text.find("file="); at != std::string::npos; at = text.find("file=", at + 5)) {
      files.insert(text.substr(at + 5, text.find_first_of(" \t\n", at) - at - 5));
    }
    EXPECT_LE(files.size(), 8u) << text;
    for (const char* heavy : {"imgcodecs", "libgdal", "libsqlite3", "libcurl", "libassimp", "libEGL", "liblcm"}) {
      EXPECT_EQ(text.find(heavy), std::string::npos) << "mtg --help loaded " << heavy;
    }
  }
  {
    const auto [status, text] = loaded_by({testing::bin("mtg_cli"), "--help"}, log);
    EXPECT_EQ(status, 0) << text;
    EXPECT_NE(text.find("libsqlite3"), std::string::npos) << "LD_DEBUG did not report the loads";
    EXPECT_EQ(text.find("imgcodecs"), std::string::npos) << "mtg_cli --help loaded the image codecs";
  }
  {
    const auto [status, text] = loaded_by({testing::bin("mtg"), "tasks", "--data", fx.root().string(), "--scene",
                                           "two_tables", "--levels", "1,2", "--out", (fx.root() / "t.sqlite").string()},
                                          log);
    EXPECT_EQ(status, 0) << text;
    EXPECT_NE(text.find("mtg_cli"), std::string::npos) << "the front ran mtg_cli";
    EXPECT_EQ(text.find("imgcodecs"), std::string::npos) << "mtg tasks loaded the image codecs";
  }
  EXPECT_TRUE(fs::exists(fs::path(testing::bin("mtg")).parent_path() / "libmtg_imgcodecs.so"));
}

// The front copied alone still answers --help, and a command says in one line what is missing.
TEST(Startup, TheFrontWithoutMtgCliSaysWhatIsMissing) {
  testing::FixtureDataset fx;
  const fs::path alone = fx.root() / "alone" / "mtg";
  fs::create_directories(alone.parent_path());
  fs::copy_file(testing::bin("mtg"), alone);
  const fs::path log = fx.root() / "alone.log";
  {
    testing::ChildProcess p({alone.string(), "--help"}, log.string());
    EXPECT_EQ(p.wait(30000), 0) << testing::read_text(log);
  }
  testing::ChildProcess p({alone.string(), "scene", "list"}, log.string());
  EXPECT_EQ(p.wait(30000), 1) << testing::read_text(log);
  EXPECT_NE(testing::read_text(log).find("mtg: cannot run " + (alone.parent_path() / "mtg_cli").string() +
                                ": No such file or directory"),
            std::string::npos)
      << testing::read_text(log);
}

TEST(Startup, TheLoadedCodecsDecodeAndEncodeAsOpenCvDoes) {
  cv::Mat image(48, 64, CV_8UC3);
  cv::randu(image, 0, 255);
  std::vector<std::uint8_t> png, jpeg_direct, jpeg_module;
  ASSERT_TRUE(cv::imencode(".png", image, png));
  const cv::Mat decoded = render::decode_color_image(png);
  ASSERT_EQ(decoded.size(), image.size());
  EXPECT_EQ(cv::norm(decoded, image, cv::NORM_INF), 0.0);
  ASSERT_TRUE(cv::imencode(".jpg", image, jpeg_direct, {cv::IMWRITE_JPEG_QUALITY, 90}));
  ASSERT_TRUE(render::encode_with_imgcodecs(".jpg", image, jpeg_module, {render::kJpegQualityFlag, 90}));
  EXPECT_EQ(jpeg_module, jpeg_direct);
  EXPECT_TRUE(render::decode_color_image(std::vector<std::uint8_t>{1, 2, 3}).empty());
  EXPECT_TRUE(render::imgcodecs_loaded());
}

}  // namespace
}  // namespace mtg
