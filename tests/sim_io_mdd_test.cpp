// MDD point caches (big-endian, times in seconds): round trip, byte layout, bad input.
#include <gtest/gtest.h>

#include "sim_io/load_sequence.hpp"
#include "sim_io/mdd_format.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io_fixtures.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::TempDir;

TEST(SimIoMdd, RoundTripWithObjKeepsTimes) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(3, 3, 4);
  write_obj(dir / "s.obj", sheet.topology(), sheet.frame(0).positions);
  write_mdd(dir / "s.mdd", test::all_positions(sheet), {0.0, 0.5, 1.0, 1.5});
  const MeshSequence loaded = load_sequence(dir / "s.obj", dir / "s.mdd");
  EXPECT_EQ(test::all_positions(loaded), test::all_positions(sheet));
  EXPECT_DOUBLE_EQ(loaded.frame_time(3), 1.5);
  EXPECT_DOUBLE_EQ(loaded.frame_rate(), 2.0);
}

TEST(SimIoMdd, BigEndianLayout) {
  TempDir dir;
  write_mdd(dir / "t.mdd", {{{1.0, 2.0, -2.0}}}, {0.25});
  const std::string expected = std::string("\x00\x00\x00\x01\x00\x00\x00\x01", 8) +
                               std::string("\x3e\x80\x00\x00", 4) +
                               std::string("\x3f\x80\x00\x00\x40\x00\x00\x00\xc0\x00\x00\x00", 12);
  EXPECT_EQ(test::slurp(dir / "t.mdd"), expected);
  const MddHeader h = read_mdd_header(dir / "t.mdd");
  EXPECT_EQ(h.num_frames, 1);
  EXPECT_EQ(h.num_points, 1);
  EXPECT_EQ(open_mdd(dir / "t.mdd")->read_frame(0), (std::vector<glm::dvec3>{{1.0, 2.0, -2.0}}));
}

std::string place_of(const std::filesystem::path& p) {
  try {
    const auto source = open_mdd(p);
    for (std::size_t i = 0; i < source->num_frames(); ++i) source->read_frame(i);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p.string());
    return e.place();
  }
  return "no error";
}

TEST(SimIoMdd, BadInputNamesThePlace) {
  TempDir dir;
  write_mdd(dir / "ok.mdd", {{{0, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}}}, {0.0, 1.0});
  const std::string ok = test::slurp(dir / "ok.mdd");
  test::write_bytes(dir / "a.mdd", ok.substr(0, ok.size() - 1));
  EXPECT_EQ(place_of(dir / "a.mdd"), "byte " + std::to_string(ok.size() - 1));
  test::write_bytes(dir / "b.mdd", ok.substr(0, 6));
  EXPECT_EQ(place_of(dir / "b.mdd"), "byte 6");
  std::string bad = ok;
  bad[0] = char(0xff);  // negative frame count
  test::write_bytes(dir / "c.mdd", bad);
  EXPECT_EQ(place_of(dir / "c.mdd"), "byte 0");
  bad = ok;
  bad[12] = 0;  // second time 0: not increasing
  bad[13] = 0;
  test::write_bytes(dir / "d.mdd", bad);
  EXPECT_EQ(place_of(dir / "d.mdd"), "byte 12");
  bad = ok;
  bad[16 + 12 + 4] = char(0x7f);  // frame 0, vertex 1, y = NaN
  bad[16 + 12 + 5] = char(0xc0);
  test::write_bytes(dir / "e.mdd", bad);
  EXPECT_EQ(place_of(dir / "e.mdd"), "frame 0, vertex 1");
}

}  // namespace
}  // namespace pleat
