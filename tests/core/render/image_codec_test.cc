#include "core/render/image_codec.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace mtg::render {
namespace {

TEST(ColorProfile, TheIccpChunkGoesAndEveryOtherByteStays) {
  cv::Mat image(4, 5, CV_8UC3, cv::Scalar(10, 200, 30));
  const std::vector<std::uint8_t> plain = encode_image(image, "png");
  // A profile chunk after IHDR (8 + 25 bytes), as the dataset's textures have.
  std::vector<std::uint8_t> profiled(plain.begin(), plain.begin() + 33);
  const std::string body = "sRGB IEC61966-2.1";
  const std::uint32_t n = static_cast<std::uint32_t>(body.size());
  for (int shift : {24, 16, 8, 0}) profiled.push_back(static_cast<std::uint8_t>(n >> shift));
  for (char c : std::string("iCCP") + body + "CRC!") profiled.push_back(static_cast<std::uint8_t>(c));
  profiled.insert(profiled.end(), plain.begin() + 33, plain.end());
  EXPECT_EQ(without_color_profile(profiled), plain);
  EXPECT_EQ(without_color_profile(plain), plain);
  // Not a PNG, or a torn one: as it was.
  const std::vector<std::uint8_t> jpeg = encode_image(image, "jpeg");
  EXPECT_EQ(without_color_profile(jpeg), jpeg);
  const std::vector<std::uint8_t> torn(profiled.begin(), profiled.begin() + 40);
  EXPECT_EQ(without_color_profile(torn), torn);
}

}  // namespace
}  // namespace mtg::render
