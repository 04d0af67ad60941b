// `pleat compare`: runs end to end on a tiny generated cloth, writes a PNG of three labelled panels and
// prints the one-line summary; rejects a frame out of range and a non-PNG output with a clear message.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.hpp"

namespace pleat {
namespace {

bool has_png_signature(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 8> head{};
  in.read(head.data(), head.size());
  const std::array<unsigned char, 8> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  for (std::size_t i = 0; i < png.size(); ++i)
    if (static_cast<unsigned char>(head[i]) != png[i]) return false;
  return in.good();
}

TEST(CompareCommand, WritesAPngAndASummaryOnATinyCloth) {
  test::TempDir dir;
  const std::string d = dir.path().string();
  ASSERT_EQ(test::run_pleat("generate curtain -o " + d + "/c.obj --resolution 10 --frames 3").exit_code, 0);
  const auto result = test::run_pleat(
      "compare " + d + "/c.obj --cache " + d + "/c.pc2 --frame 1 --light sky:0.5 " +
      "--light point:0.3,-0.8,1.2,I=3 --paths 16 --width 64 --height 48 -o " + d + "/out/compare.png");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(has_png_signature(dir / "out/compare.png"));
  EXPECT_NE(result.output.find("mean"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("p95"), std::string::npos) << result.output;
  // Three 64-pixel panels and two gaps: wider than three panels.
  std::ifstream png(dir / "out/compare.png", std::ios::binary);
  std::array<unsigned char, 24> header{};
  png.read(reinterpret_cast<char*>(header.data()), header.size());
  const unsigned width = (header[16] << 24) | (header[17] << 16) | (header[18] << 8) | header[19];
  EXPECT_GE(width, 3u * 64u);
}

TEST(CompareCommand, RejectsAFrameOutOfRangeAndANonPngOutput) {
  test::TempDir dir;
  const std::string d = dir.path().string();
  ASSERT_EQ(test::run_pleat("generate curtain -o " + d + "/c.obj --resolution 6 --frames 2").exit_code, 0);
  const auto late = test::run_pleat("compare " + d + "/c.obj --cache " + d +
                                    "/c.pc2 --frame 5 --light sky:1 " + "--paths 4 -o " + d + "/late.png");
  EXPECT_NE(late.exit_code, 0);
  EXPECT_NE(late.output.find("--frame"), std::string::npos) << late.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "late.png"));
  const auto jpeg = test::run_pleat("compare " + d + "/c.obj --cache " + d +
                                    "/c.pc2 --light sky:1 --paths 4 -o " + d + "/x.jpg");
  EXPECT_NE(jpeg.exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "x.jpg"));
}

}  // namespace
}  // namespace pleat
