// PC2 point caches: the hand-written golden file, round trips, header validation, and a property that
// random corruptions either load or throw InputError.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cstdlib>

#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io_fixtures.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::TempDir;

// Fixed rapidcheck seed and a few hundred cases per property, unless RC_PARAMS is set by the caller.
const bool kRapidcheckParams = [] {
  return ::setenv("RC_PARAMS", "seed=20240611 max_success=300", 0) == 0;
}();

TEST(SimIoPc2, GoldenFileReadsAsWrittenByHand) {
  const auto path = test::source_dir() / "tests/golden/tiny.pc2";
  const Pc2Header h = read_pc2_header(path);
  EXPECT_EQ(h.num_points, 2);
  EXPECT_EQ(h.num_samples, 2);
  EXPECT_EQ(h.start_frame, 1.0f);
  EXPECT_EQ(h.sample_rate, 1.0f);
  const auto source = open_pc2(path, 24.0);
  EXPECT_DOUBLE_EQ(source->frame_time(0), 1.0 / 24.0);
  EXPECT_DOUBLE_EQ(source->frame_time(1), 2.0 / 24.0);
  EXPECT_EQ(source->read_frame(1), (std::vector<glm::dvec3>{{0, 1, 0}, {1, 1, 0.5}}));
  // The writer produces exactly these bytes.
  TempDir dir;
  write_pc2(dir / "t.pc2", {{{0, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0.5}}}, 1.0, 1.0);
  EXPECT_EQ(test::slurp(dir / "t.pc2"), test::slurp(path));
}

TEST(SimIoPc2, RoundTripWithObj) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(4, 3, 5);
  write_obj(dir / "s.obj", sheet.topology(), sheet.frame(0).positions);
  write_pc2(dir / "s.pc2", test::all_positions(sheet), 0.0, 1.0);
  const MeshSequence loaded = load_sequence(dir / "s.obj", dir / "s.pc2");
  EXPECT_EQ(loaded.topology().triangles, sheet.topology().triangles);
  ASSERT_EQ(loaded.num_frames(), 5u);
  EXPECT_EQ(test::all_positions(loaded), test::all_positions(sheet));
  EXPECT_NEAR(loaded.frame_rate(), 24.0, 1e-9);
  EXPECT_EQ(loaded.welded_duplicates(), 0u);
}

TEST(SimIoPc2, SampleRateAndStartFrameGiveTimes) {
  TempDir dir;
  write_pc2(dir / "t.pc2", {{{0, 0, 0}}, {{1, 0, 0}}, {{2, 0, 0}}}, 10.0, 2.0);
  const auto source = open_pc2(dir / "t.pc2", 30.0);
  EXPECT_DOUBLE_EQ(source->frame_time(0), 10.0 / 30.0);
  EXPECT_DOUBLE_EQ(source->frame_time(2), 14.0 / 30.0);
}

std::string place_of(const std::filesystem::path& p) {
  try {
    read_pc2_header(p);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p.string());
    return e.place();
  }
  return "no error";
}

TEST(SimIoPc2, HeaderErrorsNameTheByte) {
  TempDir dir;
  const auto golden = test::slurp(test::source_dir() / "tests/golden/tiny.pc2");
  std::string bad = golden;
  bad[0] = 'X';
  test::write_bytes(dir / "magic.pc2", bad);
  EXPECT_EQ(place_of(dir / "magic.pc2"), "byte 0");
  test::write_bytes(dir / "short.pc2", golden.substr(0, golden.size() - 5));
  EXPECT_EQ(place_of(dir / "short.pc2"), "byte " + std::to_string(golden.size() - 5));
  test::write_bytes(dir / "header.pc2", golden.substr(0, 20));
  EXPECT_EQ(place_of(dir / "header.pc2"), "byte 20");
  test::write_bytes(dir / "long.pc2", golden + "xx");
  EXPECT_EQ(place_of(dir / "long.pc2"), "byte " + std::to_string(golden.size()));
  bad = golden;
  bad[24] = bad[25] = bad[26] = bad[27] = 0;  // sampleRate 0
  test::write_bytes(dir / "rate.pc2", bad);
  EXPECT_EQ(place_of(dir / "rate.pc2"), "byte 24");
  bad = golden;
  bad[19] = char(0x80);  // numPoints negative
  test::write_bytes(dir / "points.pc2", bad);
  EXPECT_EQ(place_of(dir / "points.pc2"), "byte 16");
}

TEST(SimIoPc2, NanCoordinateNamesFrameAndVertex) {
  TempDir dir;
  std::string bytes = test::slurp(test::source_dir() / "tests/golden/tiny.pc2");
  bytes[32 + 12 + 12 + 4 + 3] = char(0x7f);  // frame 1, vertex 0, y: 0x7f800000 = +inf
  bytes[32 + 12 + 12 + 4 + 2] = char(0x80);
  test::write_bytes(dir / "inf.pc2", bytes);
  try {
    open_pc2(dir / "inf.pc2")->read_frame(1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "frame 1, vertex 0");
  }
}

TEST(SimIoPc2, VertexCountMismatchWithMesh) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(2, 2, 2);
  write_obj(dir / "s.obj", sheet.topology(), sheet.frame(0).positions);
  write_pc2(dir / "s.pc2", {{{0, 0, 0}, {1, 0, 0}}}, 0.0, 1.0);
  try {
    load_sequence(dir / "s.obj", dir / "s.pc2");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "s.pc2").string());
    EXPECT_NE(std::string(e.what()).find("mismatch"), std::string::npos);
  }
}

// Loads the corrupted cache; the only acceptable failure is InputError. Returns true if it loaded.
bool load_or_input_error(const std::filesystem::path& obj, const std::filesystem::path& pc2) {
  try {
    const MeshSequence s = load_sequence(obj, pc2);
    for (std::size_t i = 0; i < s.num_frames(); ++i) s.frame(i);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

class Pc2Corruption {
 public:
  Pc2Corruption() {
    const MeshSequence sheet = test::folding_sheet(2, 1, 3);
    write_obj(m_dir / "s.obj", sheet.topology(), sheet.frame(0).positions);
    write_pc2(m_dir / "s.pc2", test::all_positions(sheet), 0.0, 1.0);
    m_bytes = test::slurp(m_dir / "s.pc2");
  }
  const std::string& bytes() const { return m_bytes; }
  void check(const std::string& corrupted) {
    test::write_bytes(m_dir / "c.pc2", corrupted);
    load_or_input_error(m_dir / "s.obj",
                        m_dir / "c.pc2");  // any other exception or a crash fails the property
  }

 private:
  TempDir m_dir;
  std::string m_bytes;
};

RC_GTEST_PROP(SimIoPc2, BitFlipsLoadOrFailCleanly, ()) {
  static Pc2Corruption fixture;
  fixture.check(test::flip_random_bits(fixture.bytes()));
}

RC_GTEST_PROP(SimIoPc2, TruncationsLoadOrFailCleanly, ()) {
  static Pc2Corruption fixture;
  const auto size = *rc::gen::inRange<std::size_t>(0, fixture.bytes().size());
  fixture.check(fixture.bytes().substr(0, size));
}

RC_GTEST_PROP(SimIoPc2, OverwritesLoadOrFailCleanly, ()) {
  static Pc2Corruption fixture;
  std::string bytes = fixture.bytes();
  const auto at = *rc::gen::inRange<std::size_t>(0, bytes.size());
  const auto junk =
      *rc::gen::container<std::string>(*rc::gen::inRange<std::size_t>(1, 9), rc::gen::arbitrary<char>());
  for (std::size_t k = 0; k < junk.size() && at + k < bytes.size(); ++k) bytes[at + k] = junk[k];
  fixture.check(bytes);
}

}  // namespace
}  // namespace pleat
