// A frame costs what its own cloth spans (static_core/slicing_plan.hpp, planes_for_frame): a lattice plan's
// planes are taken per frame, so another frame's extent (an exploded vertex, a stray triangle) changes
// nothing; the planes beyond a frame's cloth would have offered nothing (equal output); the engines follow
// planes that come and go (kinetic = static); frames too wide or too far out are refused before allocating,
// naming the frame and the vertex.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kinetic/kinetic_visibility.hpp"
#include "oracles/test_meshes.hpp"
#include "sim_io/cloth_generators.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/visibility.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

std::vector<Frame> roll_frames(int count, double drift) {
  const ClothGenerator generator(ClothKind::Roll, {14, count, 24.0, 0});
  std::vector<Frame> frames;
  for (int f = 0; f < count; ++f) {
    frames.push_back(generator.frame(f));
    for (glm::dvec3& p : frames.back().positions) p += glm::dvec3(drift * f, 0.3 * drift * f, 0.0);
  }
  return frames;
}

TEST(FrameExtent, PlanesBeyondTheFramesClothChangeNothing) {
  // The lattice taken per frame against the same lattice's planes listed over a box ten times wider (what a
  // plan over every frame's box was): the same values, bit for bit, with a tenth of the planes or fewer.
  const ClothGenerator generator(ClothKind::Roll, {14, 3, 24.0, 0});
  for (int f = 0; f < 3; ++f) {
    const Frame frame = generator.frame(f);
    const SlicingPlan lattice = make_diffuse_plan(generator.topology(), frame, {});
    SlicingPlan listed = lattice;
    Bounds wide = cloth_bounds(generator.topology(), frame);
    const glm::dvec3 size = wide.hi - wide.lo;
    wide.lo -= 5.0 * size;
    wide.hi += 5.0 * size;
    cover_with_planes(listed, wide);
    listed.spacing = 0;  // placed planes: the engines take them as they are
    std::vector<SlicingPlane> own;
    planes_for_frame(lattice, cloth_vertices(generator.topology()), frame, own);
    EXPECT_LT(own.size() * 8, listed.planes.size());
    const FrameVisibility a = compute_visibility(generator.topology(), frame, lattice);
    const FrameVisibility b = compute_visibility(generator.topology(), frame, listed);
    for (const Side side : kBothSides)
      for (Index v = 0; v < generator.topology().num_vertices; ++v)
        ASSERT_EQ(a.measure(side, v).sky_visibility, b.measure(side, v).sky_visibility) << f << " " << v;
  }
}

TEST(FrameExtent, KineticEqualsStaticAsTheClothCrossesTheLattice) {
  // The cloth drifts a third of its size a frame: planes enter and leave the frame's set every frame.
  const ClothGenerator generator(ClothKind::Roll, {14, 8, 24.0, 0});
  const std::vector<Frame> frames = roll_frames(8, 0.4);
  const SlicingPlan plan = make_diffuse_plan(generator.topology(), frames[0], {});
  KineticVisibility kinetic(generator.topology(), plan, frames[0]);
  StaticVisibility fresh(generator.topology(), plan);
  std::size_t first_planes = 0;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const FrameVisibility& k = f == 0 ? kinetic.current() : kinetic.advance(frames[f]);
    const FrameVisibility& s = fresh.compute(frames[f]);
    if (f == 0) first_planes = s.stats.slices;
    EXPECT_EQ(k.stats.slices, s.stats.slices) << f;
    EXPECT_LT(s.stats.slices, 2 * first_planes) << f;  // its own extent, not the whole drift's
    for (const Side side : kBothSides)
      for (Index v = 0; v < generator.topology().num_vertices; ++v)
        ASSERT_EQ(k.measure(side, v).sky_visibility, s.measure(side, v).sky_visibility) << f << " " << v;
  }
}

TEST(FrameExtent, AFrameTooWideOrTooFarOutIsRefusedNamingTheVertex) {
  test::TestMesh sheet = test::flat_sheet(6, 6, 0.1);
  const SlicingPlan plan = make_diffuse_plan(sheet.topology, sheet.frame, {});
  Frame exploded = sheet.frame;
  exploded.positions[17].y = 1e5;
  try {
    StaticVisibility(sheet.topology, plan).compute(exploded);
    FAIL() << "an exploded vertex 1e5 away: a million planes at spacing 0.05";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("vertex 17"), std::string::npos) << what;
    EXPECT_NE(what.find("exploded"), std::string::npos) << what;
  }
  Frame far = sheet.frame;
  for (glm::dvec3& p : far.positions) p.x += 1e16;
  EXPECT_THROW(StaticVisibility(sheet.topology, plan).compute(far), InputError);
  for (glm::dvec3& p : far.positions) p.x = 1e15 + p.x - 1e16;  // within 2^53, but 2e16 spacings out
  try {
    StaticVisibility(sheet.topology, plan).compute(far);
    FAIL() << "planes 0.05 apart cannot be told apart 1e15 from the origin";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("from the origin"), std::string::npos) << e.what();
  }
}

/// A shell prefix limiting the address space to `kilobytes` (a farm's memory limit); none under
/// AddressSanitizer, whose shadow memory needs terabytes of address space (the runs still must succeed).
std::string memory_limit(long kilobytes) {
#if defined(__SANITIZE_ADDRESS__)
  (void)kilobytes;
  return "";
#else
  return "ulimit -v " + std::to_string(kilobytes) + "; ";
#endif
}

/// The bundled pile's cache with vertex 100 thrown to y = 1e5 in frame 40, into `dir`.
std::string exploded_pile(const test::TempDir& dir) {
  const std::string data = std::string(PLEAT_SOURCE_DIR) + "/data/pile/";
  const Pc2Header header = read_pc2_header(data + "pile.pc2");
  const auto source = open_pc2(data + "pile.pc2");
  std::vector<std::vector<glm::dvec3>> frames;
  for (int f = 0; f < header.num_samples; ++f) frames.push_back(source->read_frame(std::size_t(f)));
  frames[40][100].y = 1e5;
  write_pc2(dir / "pile.pc2", frames, header.start_frame, header.sample_rate);
  return data + "pile.obj --cache " + (dir / "pile.pc2").string();
}

TEST(FrameExtent, OneExplodedVertexTouchesOnlyItsFrame) {
  // Under a 3 GB address-space limit (a farm's memory limit): frame 0 of the exploded cache takes the planes
  // of frame 0 of the bundled one; frame 40 is refused (exit 2) naming the frame and the vertex; before, the
  // plan over every frame's box took 7 GB and died for frame 0 alone.
  test::TempDir dir;
  const std::string input = exploded_pile(dir);
  const std::string limit = memory_limit(3000000);
  const auto stats = [&](const std::string& cache_args, const std::string& name) {
    const test::CommandResult r =
        test::run_command(limit + std::string(PLEAT_EXECUTABLE) + " visibility " + cache_args +
                          " --frames 0 --engine static -q -o " + (dir / "a.csv").string() + " --stats " +
                          (dir / name).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(test::slurp(dir / name));
  };
  const std::string data = std::string(PLEAT_SOURCE_DIR) + "/data/pile/";
  const auto exploded = stats(input, "x.json");
  const auto bundled = stats(data + "pile.obj --cache " + data + "pile.pc2", "b.json");
  EXPECT_EQ(exploded["frames"][0]["slices"], bundled["frames"][0]["slices"]);
  const test::CommandResult r =
      test::run_command(limit + std::string(PLEAT_EXECUTABLE) + " visibility " + input +
                        " --frames 38:42 -q -o " + (dir / "b.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("vertex 100"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("exploded"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "b.csv"));
  // pleat info names it.
  const test::CommandResult info = test::run_pleat("info " + input);
  EXPECT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("first frame 40:"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("vertex 100 at"), std::string::npos) << info.output;
}

TEST(FrameExtent, CoordinatesBeyondExactIntegersAreRefused) {
  // A sheet 1e16 from the origin (its vertices 1000 apart, so that they stay distinct): refused with a
  // message, not an endless loop.
  test::TempDir dir;
  test::TestMesh sheet = test::flat_sheet(6, 6, 1000.0);
  for (glm::dvec3& p : sheet.frame.positions) p += glm::dvec3(1e16);
  write_obj(dir / "far.obj", sheet.topology, sheet.frame.positions);
  const test::CommandResult r =
      test::run_command("timeout 60 " + std::string(PLEAT_EXECUTABLE) + " visibility " +
                        (dir / "far.obj").string() + " -q -o " + (dir / "a.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("2^53"), std::string::npos) << r.output;
}

TEST(FrameExtent, ASpacingTooFineIsRefusedBeforeAllocating) {
  // --spacing 3e-7 on the drape: hundreds of millions of planes; refused under a 1 GB limit, not killed.
  const std::string data = std::string(PLEAT_SOURCE_DIR) + "/data/drape/";
  test::TempDir dir;
  const test::CommandResult r = test::run_command(
      memory_limit(1000000) + std::string(PLEAT_EXECUTABLE) + " visibility " + data + "drape.obj --cache " +
      data + "drape.pc2 --frames 0 --spacing 3e-7 -q -o " + (dir / "a.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("planes"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace pleat
