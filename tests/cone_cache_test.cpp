// The cone cache (shading/cone_cache.hpp): frames round-trip exactly, bad caches (truncated, foreign, another
// version, another mesh, a frame not cached, a corrupt block) fail with one InputError naming the file and
// the place, a changed byte anywhere is named as damage (the checksums), caches of the versions without
// checksums are still read, and at the command line shading from a cache writes the same glb as shading from
// fresh cones.
#include "shading/cone_cache.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <iterator>
#include <random>

#include "shading/shade.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/visibility.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::slurp;

void spit(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

std::uint64_t le_at(const std::string& bytes, std::size_t at, int size) {
  std::uint64_t value = 0;
  for (int k = size - 1; k >= 0; --k) value = value << 8 | std::uint8_t(bytes[at + std::size_t(k)]);
  return value;
}

/// The same cache as written by a pleat before checksums (version 1, or 2 for compact): the table's checksums
/// dropped and the frames' offsets moved back over them.
std::string without_checksums(const std::string& cache) {
  const std::size_t table = le_at(cache, 12, 4), frames = le_at(cache, 28, 4), removed = 4 * frames + 4;
  std::string old = cache.substr(0, table);
  old[8] = char(cache[8] == 3 ? 1 : 2);
  for (std::size_t k = 0; k <= frames; ++k) {
    const std::uint64_t offset = le_at(cache, table + 8 * k, 8) - removed;
    for (int b = 0; b < 8; ++b) old += char((offset >> (8 * b)) & 0xFF);
  }
  return old + cache.substr(table + 8 * (frames + 1) + removed);
}

/// The message of the InputError `f` throws, or "" when it throws none.
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

struct Fixture {
  ClothGenerator cloth{ClothKind::Roll, {10, 12, 24.0, 3}};
  std::vector<Index> identity;
  std::vector<FrameVisibility> frames;
  std::vector<Frame> positions;
  Fixture() {
    for (Index v = 0; v < cloth.topology().num_vertices; ++v) identity.push_back(v);
    const SlicingPlan plan = make_diffuse_plan(cloth.topology(), cloth.frame(0), {});
    StaticVisibility engine(cloth.topology(), plan, {false});
    for (std::size_t f : {2, 5, 7}) {
      positions.push_back(cloth.frame(f));
      frames.push_back(engine.compute(positions.back()));
    }
  }
  void write(const std::filesystem::path& path) const {
    ConeCacheWriter writer(path, cloth.topology(), identity, 24.0, "test plan", {2, 5, 7});
    for (std::size_t k = 0; k < frames.size(); ++k) writer.add_frame(positions[k], frames[k]);
    writer.commit();
  }
};

TEST(ConeCache, FramesRoundTripExactlyAndInAnyOrder) {
  test::TempDir dir;
  const Fixture fx;
  fx.write(dir / "c.cones");
  ConeCacheReader reader(dir / "c.cones");
  EXPECT_EQ(reader.header().plan, "test plan");
  EXPECT_EQ(reader.header().frames, (std::vector<std::uint32_t>{2, 5, 7}));
  EXPECT_DOUBLE_EQ(reader.header().times[1], 5.0 / 24.0);
  reader.check_mesh(fx.cloth.topology(), fx.identity);
  std::size_t pieces = 0;
  const std::size_t numbers[] = {2, 5, 7};
  for (std::size_t k : {2u, 0u, 1u}) {  // a frame is read without the ones before it
    FrameVisibility got;
    reader.read_frame(reader.index_of_frame(numbers[k]), fx.positions[k], got);
    const FrameVisibility& want = fx.frames[k];
    ASSERT_EQ(got.normals, want.normals);
    for (int side = 0; side < 2; ++side) {
      ASSERT_EQ(got.measures[side].size(), want.measures[side].size());
      for (std::size_t v = 0; v < want.measures[side].size(); ++v) {
        EXPECT_EQ(got.measures[side][v].sky_visibility, want.measures[side][v].sky_visibility);
        EXPECT_EQ(got.measures[side][v].bent_normal, want.measures[side][v].bent_normal);
        EXPECT_EQ(got.measures[side][v].solid_angle, want.measures[side][v].solid_angle);
        ASSERT_EQ(got.cones[side][v].pieces, want.cones[side][v].pieces);
        pieces += want.cones[side][v].pieces.size();
      }
    }
  }
  EXPECT_GT(pieces, 100u);  // the round trip carried real cones
}

TEST(ConeCache, FramesEncodedElsewhereMakeTheSameBytes) {
  // What an MPI rank or a checkpointed chunk sends to the writer: encode_cone_frame's blocks.
  test::TempDir dir;
  const Fixture fx;
  fx.write(dir / "direct.cones");
  ConeCacheWriter writer(dir / "encoded.cones", fx.cloth.topology(), fx.identity, 24.0, "test plan",
                         {2, 5, 7});
  for (std::size_t k = 0; k < fx.frames.size(); ++k)
    writer.add_encoded_frame(encode_cone_frame(fx.positions[k], fx.frames[k]));
  // A block cut short (or from a smaller mesh) is refused before anything is written for it.
  const std::string block = encode_cone_frame(fx.positions[0], fx.frames[0]);
  ConeCacheWriter other(dir / "short.cones", fx.cloth.topology(), fx.identity, 24.0, "test plan", {2});
  EXPECT_THROW(other.add_encoded_frame(std::string_view(block).substr(0, 100)), std::invalid_argument);
  writer.commit();
  const std::string direct = slurp(dir / "direct.cones");
  EXPECT_GT(direct.size(), 3 * block.size() / 2);
  EXPECT_TRUE(direct == slurp(dir / "encoded.cones"));
}

double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

TEST(ConeCache, CompactDirectionsAreWithin5e5RadiansEverywhereOnTheSphere) {
  // One triangle whose cones hold directions over the whole sphere: the axes, the octahedron's folds and
  // faces' centres, both hemispheres, and random ones; everything but the directions round-trips exactly.
  test::TempDir dir;
  MeshTopology topology;
  topology.num_vertices = 3;
  topology.triangles = {{0, 1, 2}};
  Frame frame;
  frame.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  FrameVisibility vis;
  vis.normals.assign(3, glm::dvec3(0, 0, 1));
  std::vector<glm::dvec3> directions;
  for (int axis = 0; axis < 3; ++axis)
    for (double s : {-1.0, 1.0}) {
      glm::dvec3 d(0.0);
      d[axis] = s;
      directions.push_back(d);
    }
  for (double x : {-1.0, 1.0})
    for (double y : {-1.0, 1.0}) {
      directions.push_back(glm::normalize(glm::dvec3(x, y, 0)));                               // on the fold
      for (double z : {-1.0, 1.0}) directions.push_back(glm::normalize(glm::dvec3(x, y, z)));  // face centres
      directions.push_back(glm::normalize(glm::dvec3(x, y, -1e-9)));  // just below the equator
    }
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  while (directions.size() < 20000)
    directions.push_back(glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng))));
  for (int side = 0; side < 2; ++side) {
    vis.measures[side].assign(3, ConeMeasures{0.25, glm::dvec3(0, 0.6, 0.8), 1.5});
    vis.cones[side].resize(3);
    for (int v = 0; v < 3; ++v) vis.cones[side][v].pieces.push_back(directions);
  }
  ConeCacheWriter writer(dir / "c.cones", topology, std::vector<Index>{0, 1, 2}, 0.0, "p", {0},
                         ConeEncoding::Compact);
  writer.add_frame(frame, vis);
  writer.commit();
  ConeCacheReader reader(dir / "c.cones");
  EXPECT_EQ(reader.header().encoding, ConeEncoding::Compact);
  FrameVisibility got;
  reader.read_frame(0, frame, got);
  double worst = 0.0;
  for (int side = 0; side < 2; ++side)
    for (int v = 0; v < 3; ++v) {
      EXPECT_EQ(got.measures[side][v].sky_visibility, 0.25);
      EXPECT_EQ(got.measures[side][v].bent_normal, glm::dvec3(0, 0.6, 0.8));
      ASSERT_EQ(got.cones[side][v].pieces.size(), 1u);
      const SphericalPolygon& piece = got.cones[side][v].pieces[0];
      ASSERT_EQ(piece.size(), directions.size());
      for (std::size_t k = 0; k < piece.size(); ++k) {
        EXPECT_NEAR(glm::length(piece[k]), 1.0, 1e-15);
        worst = std::max(worst, angle_between(piece[k], directions[k]));
      }
    }
  EXPECT_LE(worst,
            5e-5);  // measured 4.2e-5 here; 16-bit octahedral coordinates, nearest of four: 4.8e-5 at most
  EXPECT_GT(worst, 1e-6);  // they were quantised
}

TEST(ConeCache, CompactCachesAreAThirdOfTheSizeAndShadeAlike) {
  test::TempDir dir;
  const Fixture fx;
  fx.write(dir / "exact.cones");
  ConeCacheWriter writer(dir / "compact.cones", fx.cloth.topology(), fx.identity, 24.0, "test plan",
                         {2, 5, 7}, ConeEncoding::Compact);
  for (std::size_t k = 0; k < fx.frames.size(); ++k) writer.add_frame(fx.positions[k], fx.frames[k]);
  writer.commit();
  const auto exact_size = std::filesystem::file_size(dir / "exact.cones");
  const auto compact_size = std::filesystem::file_size(dir / "compact.cones");
  EXPECT_LT(double(compact_size), 0.4 * double(exact_size)) << compact_size << " of " << exact_size;
  // Shading from the compact cache: a sky and a sun, radiance within 1e-4 of the exact cones' (relative to
  // the frame's brightest vertex).
  ConeCacheReader reader(dir / "compact.cones");
  Lighting lighting;
  lighting.lights.push_back(UniformSkyLight{});
  lighting.lights.push_back(DirectionalLight{});
  for (std::size_t k = 0; k < fx.frames.size(); ++k) {
    FrameVisibility compact;
    reader.read_frame(k, fx.positions[k], compact);
    const ShadedFrame want = shade_frame(fx.cloth.topology(), fx.positions[k], fx.frames[k], lighting);
    const ShadedFrame got = shade_frame(fx.cloth.topology(), fx.positions[k], compact, lighting);
    float brightest = 0.0f, worst = 0.0f;
    for (int side = 0; side < 2; ++side)
      for (std::size_t v = 0; v < want.radiance[side].size(); ++v) {
        brightest = std::max(brightest, glm::length(want.radiance[side][v]));
        worst = std::max(worst, glm::length(got.radiance[side][v] - want.radiance[side][v]));
      }
    EXPECT_GT(brightest, 0.0f);
    EXPECT_LE(worst, 1e-4f * brightest) << "frame " << k;
  }
}

TEST(ConeCache, BadCachesFailWithOneClearError) {
  test::TempDir dir;
  const Fixture fx;
  fx.write(dir / "good.cones");
  const std::string good = slurp(dir / "good.cones");

  spit(dir / "truncated.cones", good.substr(0, good.size() - 100));
  EXPECT_NE(input_error([&] { ConeCacheReader r(dir / "truncated.cones"); }).find("truncated"),
            std::string::npos);
  spit(dir / "header_only.cones", good.substr(0, 30));
  EXPECT_NE(input_error([&] { ConeCacheReader r(dir / "header_only.cones"); }).find("header_only.cones"),
            std::string::npos);

  spit(dir / "foreign.cones", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" + std::string(100, ' '));
  EXPECT_NE(input_error([&] { ConeCacheReader r(dir / "foreign.cones"); }).find("not a pleat cone cache"),
            std::string::npos);

  std::string future = good;
  future[8] = 5;  // version 5
  spit(dir / "future.cones", future);
  EXPECT_NE(input_error([&] { ConeCacheReader r(dir / "future.cones"); }).find("version 5"),
            std::string::npos);

  ConeCacheReader reader(dir / "good.cones");
  MeshTopology other = fx.cloth.topology();  // the same counts, one triangle wound the other way
  std::swap(other.triangles[0][0], other.triangles[0][1]);
  EXPECT_NE(input_error([&] { reader.check_mesh(other, fx.identity); }).find("other triangles"),
            std::string::npos);
  std::vector<Index> other_order = fx.identity;
  std::swap(other_order[0], other_order[1]);
  EXPECT_NE(input_error([&] { reader.check_mesh(fx.cloth.topology(), other_order); }).find("different mesh"),
            std::string::npos);
  const ClothGenerator smaller(ClothKind::Roll, {9, 12, 24.0, 3});
  EXPECT_NE(input_error([&] { reader.check_mesh(smaller.topology(), fx.identity); }).find("different mesh"),
            std::string::npos);
  EXPECT_NE(input_error([&] { reader.index_of_frame(3); }).find("frame 3"), std::string::npos);

  // Inside frame 5's block (the second) of a cache without checksums (whose reading checks every count and
  // number): a piece count far too large, and a coordinate that is not a number.
  const std::string old = without_checksums(good);
  const std::size_t table = le_at(old, 12, 4);
  const std::size_t block = le_at(old, table + 8, 8);  // offset[1]
  const std::size_t vertices = fx.cloth.topology().num_vertices;
  std::string corrupt = old;
  const std::size_t first_count = block + 8 + 24 * vertices + 40 * vertices;
  for (int k = 0; k < 4; ++k) corrupt[first_count + k] = char(0xFF);
  spit(dir / "corrupt.cones", corrupt);
  ConeCacheReader corrupt_reader(dir / "corrupt.cones");
  FrameVisibility frame;
  const std::string early = input_error([&] { corrupt_reader.read_frame(1, fx.positions[1], frame); });
  EXPECT_NE(early.find("corrupt.cones:frame 5"), std::string::npos) << early;
  EXPECT_NE(early.find("ends early"), std::string::npos) << early;
  corrupt_reader.read_frame(0, fx.positions[0], frame);  // the other frames stay readable
  // Frame 5's cones read against frame 7's positions: another simulation.
  EXPECT_NE(input_error([&] {
              ConeCacheReader(dir / "good.cones").read_frame(1, fx.positions[2], frame);
            }).find("other positions"),
            std::string::npos);

  std::string nan = old;
  for (int k = 0; k < 8; ++k) nan[block + 8 + k] = char(0xFF);  // the first normal's x: a NaN
  spit(dir / "nan.cones", nan);
  ConeCacheReader nan_reader(dir / "nan.cones");
  EXPECT_NE(input_error([&] { nan_reader.read_frame(1, fx.positions[1], frame); }).find("not finite"),
            std::string::npos);
}

TEST(ConeCache, CachesWithoutChecksumsAreStillRead) {
  test::TempDir dir;
  const Fixture fx;
  fx.write(dir / "new.cones");
  spit(dir / "old.cones", without_checksums(slurp(dir / "new.cones")));
  ConeCacheReader reader(dir / "old.cones");
  for (std::size_t k = 0; k < fx.frames.size(); ++k) {
    FrameVisibility frame;
    reader.read_frame(k, fx.positions[k], frame);
    EXPECT_EQ(frame.measures[0].size(), fx.frames[k].measures[0].size());
    EXPECT_EQ(frame.measures[0][3].sky_visibility, fx.frames[k].measures[0][3].sky_visibility);
  }
}

TEST(ConeCache, AChangedByteAnywhereIsNamedAsDamage) {
  // About 250 bytes spread over the file flipped in turn: opening the cache or reading the frame that holds
  // it fails with an InputError; past the header (magic, version), the message says the cache is damaged, and
  // inside a frame it names the frame. The other frames stay readable.
  test::TempDir dir;
  const Fixture fx;
  fx.write(dir / "good.cones");
  const std::string good = slurp(dir / "good.cones");
  const std::size_t table = le_at(good, 12, 4);
  std::vector<std::size_t> starts;
  for (std::size_t k = 0; k <= fx.frames.size(); ++k) starts.push_back(le_at(good, table + 8 * k, 8));
  const std::uint32_t numbers[] = {2, 5, 7};
  std::size_t checked = 0;
  const std::size_t step = std::max<std::size_t>(37, good.size() / 250) | 1;  // about 250 places, all kinds
  for (std::size_t at = 12; at < good.size(); at += step) {
    std::string damaged = good;
    damaged[at] = char(damaged[at] ^ 0x04);
    spit(dir / "damaged.cones", damaged);
    std::string error = input_error([&] {
      ConeCacheReader reader(dir / "damaged.cones");
      for (std::size_t k = 0; k < fx.frames.size(); ++k) {
        FrameVisibility frame;
        reader.read_frame(k, fx.positions[k], frame);
      }
    });
    ASSERT_NE(error, "") << "byte " << at << " changed and nothing noticed";
    EXPECT_NE(error.find("damaged cone cache"), std::string::npos) << "byte " << at << ": " << error;
    if (at >= starts.front()) {
      const std::size_t k =
          std::size_t(std::upper_bound(starts.begin(), starts.end(), at) - starts.begin()) - 1;
      EXPECT_NE(error.find("damaged.cones:frame " + std::to_string(numbers[k])), std::string::npos)
          << "byte " << at << ": " << error;
      ConeCacheReader reader(dir / "damaged.cones");  // the others still read
      FrameVisibility frame;
      const std::size_t other = (k + 1) % fx.frames.size();
      EXPECT_EQ(input_error([&] { reader.read_frame(other, fx.positions[other], frame); }), "");
    }
    ++checked;
  }
  EXPECT_GT(checked, 200u);
}

/// The acceptance check at the command line: cones once (`pleat visibility --cones`), then `pleat shade
/// --cones` writes the same glb as `pleat shade` computing them, for both engines' caches; a cache of another
/// mesh fails with one line and writes no glb.
TEST(ConeCache, ShadingFromTheCacheEqualsShadingFromFreshCones) {
  test::TempDir dir;
  const std::string obj = (dir / "c.obj").string(), pc2 = (dir / "c.pc2").string();
  ASSERT_EQ(test::run_pleat("generate roll -o " + obj + " --resolution 12 --frames 8").exit_code, 0);
  const std::string input = obj + " --cache " + pc2 + " --frames 2:6";
  for (const std::string engine : {"static", "kinetic"}) {
    const auto v = test::run_pleat("visibility " + input + " -o " + (dir / "a.csv").string() + " --engine " +
                                   engine + " --cones " + (dir / (engine + ".cones")).string());
    ASSERT_EQ(v.exit_code, 0) << v.output;
  }
  const std::string light = " --light sky:0.5 --light dir:0.3,-1,0.2,E=2";
  const auto fresh = test::run_pleat("shade " + input + " -o " + (dir / "fresh.glb").string() + light);
  ASSERT_EQ(fresh.exit_code, 0) << fresh.output;
  for (const std::string engine : {"static", "kinetic"}) {
    const auto cached = test::run_pleat("shade " + input + " -o " + (dir / "cached.glb").string() + light +
                                        " --cones " + (dir / (engine + ".cones")).string());
    ASSERT_EQ(cached.exit_code, 0) << cached.output;
    EXPECT_NE(cached.output.find("read from"), std::string::npos) << cached.output;
    EXPECT_TRUE(slurp(dir / "fresh.glb") == slurp(dir / "cached.glb")) << engine << ": the glbs differ";
  }
  // Several lighting setups (--relight) from the cache: each equals its freshly computed twin.
  const std::string setups = (dir / "setups.json").string();
  {
    std::ofstream(setups) << R"({"setups": [{"name": "noon", "lights": ["sky:1"]},)"
                          << R"( {"name": "dusk", "lights": ["sky:0.2", "dir:0.3,-1,0.2,E=2"]}]})";
  }
  const auto relit =
      test::run_pleat("shade " + input + " -o " + (dir / "r.glb").string() + " --relight " + setups);
  ASSERT_EQ(relit.exit_code, 0) << relit.output;
  const auto relit_cached =
      test::run_pleat("shade " + input + " -o " + (dir / "rc.glb").string() + " --relight " + setups +
                      " --cones " + (dir / "static.cones").string());
  ASSERT_EQ(relit_cached.exit_code, 0) << relit_cached.output;
  for (const std::string name : {"noon", "dusk"})
    EXPECT_TRUE(slurp(dir / ("r_" + name + ".glb")) == slurp(dir / ("rc_" + name + ".glb"))) << name;

  // A compact cache from the command line: a third of the size, and shading reads it.
  const auto compact =
      test::run_pleat("visibility " + input + " -o " + (dir / "a.csv").string() + " --cones " +
                      (dir / "compact.cones").string() + " --cones-encoding compact");
  ASSERT_EQ(compact.exit_code, 0) << compact.output;
  EXPECT_LT(double(std::filesystem::file_size(dir / "compact.cones")),
            0.4 * double(std::filesystem::file_size(dir / "static.cones")));
  const auto from_compact = test::run_pleat("shade " + input + " -o " + (dir / "compact.glb").string() +
                                            light + " --cones " + (dir / "compact.cones").string());
  ASSERT_EQ(from_compact.exit_code, 0) << from_compact.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "compact.glb"));

  // Frames outside the cache, and a cache of another mesh: one line, exit 2, no glb.
  const auto missing =
      test::run_pleat("shade " + obj + " --cache " + pc2 + " --frames 0:4 -o " +
                      (dir / "missing.glb").string() + " --cones " + (dir / "static.cones").string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("frame 0"), std::string::npos) << missing.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "missing.glb"));
  const std::string other = (dir / "o.obj").string();
  ASSERT_EQ(test::run_pleat("generate curtain -o " + other + " --resolution 12 --frames 8").exit_code, 0);
  const auto wrong =
      test::run_pleat("shade " + other + " --cache " + (dir / "o.pc2").string() + " --frames 2:6 -o " +
                      (dir / "wrong.glb").string() + " --cones " + (dir / "static.cones").string());
  EXPECT_EQ(wrong.exit_code, 2) << wrong.output;
  EXPECT_NE(wrong.output.find("other positions"), std::string::npos) << wrong.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "wrong.glb"));
}

TEST(ConeCache, ShadeRefusesADamagedCacheWithoutWritingAGlb) {
  test::TempDir dir;
  const std::string input = (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string();
  ASSERT_EQ(test::run_pleat("generate roll -o " + (dir / "c.obj").string() + " --resolution 12 --frames 4")
                .exit_code,
            0);
  const auto v = test::run_pleat("visibility " + input + " -o " + (dir / "a.csv").string() + " --cones " +
                                 (dir / "c.cones").string());
  ASSERT_EQ(v.exit_code, 0) << v.output;
  std::string cones = slurp(dir / "c.cones");
  cones[cones.size() - 1000] = char(cones[cones.size() - 1000] ^ 1);  // in the last frame's block
  spit(dir / "c.cones", cones);
  const auto shaded = test::run_pleat("shade " + input + " -o " + (dir / "s.glb").string() + " --cones " +
                                      (dir / "c.cones").string());
  EXPECT_EQ(shaded.exit_code, 2) << shaded.output;
  EXPECT_NE(shaded.output.find("c.cones:frame 3, bytes "), std::string::npos) << shaded.output;
  EXPECT_NE(shaded.output.find("damaged cone cache: the frame's checksum does not match"), std::string::npos)
      << shaded.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "s.glb"));
}

}  // namespace
}  // namespace pleat
