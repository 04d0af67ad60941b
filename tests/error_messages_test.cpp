// What pleat says when something is wrong, with the file and the place: a full disk ("no space left on
// device", a file size limit), a little-endian MDD, a UTF-16 or binary file given as an OBJ, a spacing too
// fine for the cloth or not finite, a truncated HDR environment map. Each is one line, exit status 1
// (runtime) or 2 (bad input), and leaves no output.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "shading/environment_map.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::names_in;
using test::slurp;
namespace fs = std::filesystem;

class ErrorMessages : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto made =
        test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 8 --frames 3");
    ASSERT_EQ(made.exit_code, 0) << made.output;
  }
  std::string input() const { return (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string(); }
  // The entries of the directory other than the inputs the fixture made.
  std::vector<std::string> left() const {
    std::vector<std::string> names;
    for (const std::string& name : names_in(dir.path()))
      if (name != "c.obj" && name != "c.pc2" && name != "errors.txt") names.push_back(name);
    return names;
  }
  test::TempDir dir;
};

TEST_F(ErrorMessages, AFullDiskNamesTheFileAndTheReason) {
  // Standard output on a full device (/dev/full), the other output's temporary removed.
  const auto full = test::run_command("(" + std::string(PLEAT_EXECUTABLE) + " visibility " + input() +
                                      " -o - --cones " + (dir / "v.cones").string() + " > /dev/full)");
  EXPECT_EQ(full.exit_code, 1) << full.output;
  EXPECT_NE(full.output.find("pleat: error: standard output: cannot write: no space left on device"),
            std::string::npos)
      << full.output;
  EXPECT_EQ(left(), std::vector<std::string>{});
  // A file past the file size limit (`ulimit -f`): the file named, and why.
  const pid_t pid =
      test::start_pleat({"visibility", (dir / "c.obj").string(), "--cache", (dir / "c.pc2").string(), "-o",
                         (dir / "v.csv").string(), "--cones", (dir / "v.cones").string()},
                        dir / "errors.txt", {.limits = {{RLIMIT_FSIZE, rlimit{20000, 20000}}}});
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(slurp(dir / "errors.txt")
                .find("v.cones: cannot write: file too large (over the file size limit, ulimit -f)"),
            std::string::npos)
      << slurp(dir / "errors.txt");
  EXPECT_EQ(left(), std::vector<std::string>{});
}

TEST_F(ErrorMessages, AFullFileSystemNamesTheFile) {
  // A real full file system: a 200 KB tmpfs in a mount namespace of its own (needs the right to mount).
  if (test::run_command("unshare -m true").exit_code != 0) GTEST_SKIP() << "no mount namespaces here";
  fs::create_directories(dir / "small");
  const auto run = test::run_command(
      "unshare -m sh -c 'mount -t tmpfs -o size=200k none " + (dir / "small").string() + " && " +
      PLEAT_EXECUTABLE + " visibility " + input() + " -o " + (dir / "small/v.csv").string() + " --cones " +
      (dir / "small/v.cones").string() + "; echo \"exit $?\"; ls -A " + (dir / "small").string() + "'");
  if (run.output.find("exit ") == std::string::npos) GTEST_SKIP() << "cannot mount a tmpfs: " << run.output;
  EXPECT_NE(run.output.find("exit 1"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("small/v.cones: cannot write: no space left on device"), std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find(".tmp."), std::string::npos) << run.output;  // the listing: nothing left
}

// A little-endian int32 / float32.
void put32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out += char((v >> (8 * k)) & 0xFF);
}

TEST_F(ErrorMessages, ALittleEndianMddSaysSo) {
  // The PC2's frames as an MDD written in the wrong byte order.
  const std::string pc2 = slurp(dir / "c.pc2");
  std::uint32_t points = 0, frames = 0;
  std::memcpy(&points, pc2.data() + 16, 4);
  std::memcpy(&frames, pc2.data() + 28, 4);
  std::string mdd;
  put32(mdd, frames);
  put32(mdd, points);
  for (std::uint32_t f = 0; f < frames; ++f) {
    const float time = float(f) / 24.0f;
    std::uint32_t bits = 0;
    std::memcpy(&bits, &time, 4);
    put32(mdd, bits);
  }
  mdd += pc2.substr(32);
  std::ofstream(dir / "le.mdd", std::ios::binary) << mdd;
  const auto run =
      test::run_pleat("info " + (dir / "c.obj").string() + " --cache " + (dir / "le.mdd").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("le.mdd:byte"), std::string::npos) << run.output;
  EXPECT_NE(
      run.output.find("read little-endian, the header says " + std::to_string(frames) + " frames of " +
                      std::to_string(points) + " points, which fits the file exactly: MDD is big-endian"),
      std::string::npos)
      << run.output;
}

TEST_F(ErrorMessages, Utf16AndBinaryFilesGivenAsObjSaySo) {
  const std::string text = slurp(dir / "c.obj");
  auto utf16 = [&](bool big_endian, bool mark) {
    std::string out = mark ? (big_endian ? std::string("\xFE\xFF", 2) : std::string("\xFF\xFE", 2)) : "";
    for (char c : text) out += big_endian ? std::string{'\0', c} : std::string{c, '\0'};
    return out;
  };
  const std::pair<std::string, std::string> cases[] = {
      {utf16(false, true), "byte 0: a UTF-16 text file"},
      {utf16(false, false), "byte 0: a UTF-16 text file"},
      {utf16(true, true), "byte 0: a UTF-16 text file"},
      {std::string("v 0 0 0\nv 1 0 0\n\0\x01\x02 binary", 24), "byte 16: a binary file, not OBJ text"},
      {slurp(dir / "c.pc2"), "byte 11: a PC2 point cache, not OBJ text"}};
  for (const auto& [bytes, expected] : cases) {
    std::ofstream(dir / "x.obj", std::ios::binary | std::ios::trunc) << bytes;
    const auto run = test::run_pleat("info " + (dir / "x.obj").string());
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("x.obj:" + expected), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("empty mesh"), std::string::npos) << run.output;
  }
  // UTF-8 with a byte-order mark is text: it reads as the file without.
  std::ofstream(dir / "bom.obj", std::ios::binary) << "\xEF\xBB\xBF" << text;
  const auto plain = test::run_pleat("info " + (dir / "c.obj").string());
  const auto bom = test::run_pleat("info " + (dir / "bom.obj").string());
  ASSERT_EQ(bom.exit_code, 0) << bom.output;
  EXPECT_EQ(bom.output.substr(bom.output.find("vertices")),
            plain.output.substr(plain.output.find("vertices")));
}

TEST_F(ErrorMessages, SpacingsAreWrittenWithTheirDigits) {
  // Too fine for the cloth: the file named, the spacing as given.
  const auto fine =
      test::run_pleat("visibility " + input() + " -o " + (dir / "v.csv").string() + " --spacing 1e-7");
  EXPECT_EQ(fine.exit_code, 2) << fine.output;
  EXPECT_NE(
      fine.output.find("pleat: error: " + (dir / "c.pc2").string() + ": slicing plan: planes 1e-07 apart"),
      std::string::npos)
      << fine.output;
  // Not finite: one short line.
  for (const std::string value : {"inf", "nan", "-inf"}) {
    const auto bad =
        test::run_pleat("visibility " + input() + " -o " + (dir / "v.csv").string() + " --spacing " + value);
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
    EXPECT_NE(bad.output.find("pleat: error: --spacing: must be a finite number > 0, got " + value + "\n"),
              std::string::npos)
        << bad.output;
    EXPECT_LT(bad.output.size(), 200u) << bad.output;
  }
  // What was used, as precisely as it was given.
  const auto used = test::run_pleat("visibility " + input() + " -o " + (dir / "v.csv").string() +
                                    " --spacing 0.0123456789");
  ASSERT_EQ(used.exit_code, 0) << used.output;
  EXPECT_NE(used.output.find("spacing 0.0123456789,"), std::string::npos) << used.output;
  EXPECT_EQ(left(), std::vector<std::string>{"v.csv"});
}

TEST_F(ErrorMessages, ATruncatedHdrNamesTheByte) {
  const std::string hdr = slurp(test::source_dir() / "data/envmaps/sky_sun.hdr");
  const std::size_t header = hdr.find("\n\n") + hdr.substr(hdr.find("\n\n") + 2).find('\n') + 3;
  ASSERT_EQ(hdr.size(), header + 128 * 64 * 4);  // flat: 128 x 64 pixels of 4 bytes
  const std::pair<std::size_t, std::string> cuts[] = {{hdr.size() / 2, "the data ends in scanline 31 of 64"},
                                                      {header, "the data ends in scanline 0 of 64"}};
  for (const auto& [size, where] : cuts) {
    std::ofstream(dir / "cut.hdr", std::ios::binary | std::ios::trunc) << hdr.substr(0, size);
    const auto run = test::run_pleat("shade " + input() + " -o " + (dir / "s.glb").string() +
                                     " --light env:" + (dir / "cut.hdr").string());
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("cut.hdr:byte " + std::to_string(size) +
                              ": truncated or damaged HDR image: " + where),
              std::string::npos)
        << run.output;
    EXPECT_FALSE(fs::exists(dir / "s.glb"));
    EXPECT_THROW(EnvironmentMap::load(dir / "cut.hdr"), InputError);
  }
  // A run-length encoded map: whole, and cut inside its last scanline.
  std::string rle = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 16\n";
  for (int row = 0; row < 4; ++row) {
    rle += std::string{2, 2, 0, 16};
    for (int component = 0; component < 4; ++component)
      rle += std::string{char(128 + 16), char(component < 3 ? 100 : 128)};
  }
  std::ofstream(dir / "rle.hdr", std::ios::binary) << rle;
  EXPECT_EQ(EnvironmentMap::load(dir / "rle.hdr").width(), 16);
  std::ofstream(dir / "rle_cut.hdr", std::ios::binary) << rle.substr(0, rle.size() - 3);
  try {
    EnvironmentMap::load(dir / "rle_cut.hdr");
    ADD_FAILURE() << "a cut run-length map was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the data ends in scanline 3 of 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pleat
