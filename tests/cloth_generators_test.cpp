// The analytic cloth generators: no self-intersection (CGAL, exact) over frames, sizes and seeds; truly
// folded (normals turn far and normal rays hit the cloth); consistent winding; determinism; smooth motion;
// and `pleat generate` writing an OBJ + PC2 pair that reads back to the same frames.
#include "sim_io/cloth_generators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "sim_io/self_intersections.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

std::string name_of(ClothKind kind) { return std::string(cloth_kind_name(kind)); }

// Area-weighted vertex normals (docs/method.md §1).
std::vector<glm::dvec3> vertex_normals(const MeshTopology& topology, const Frame& frame) {
  std::vector<glm::dvec3> normals(topology.num_vertices, glm::dvec3(0.0));
  for (const auto& t : topology.triangles) {
    const auto& p = frame.positions;
    const glm::dvec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    for (Index v : t) normals[v] += n;
  }
  for (auto& n : normals) n = glm::normalize(n);
  return normals;
}

// Does the ray from vertex v in direction d hit a triangle not incident to v? (Moeller-Trumbore, brute
// force.)
bool ray_hits_cloth(const MeshTopology& topology, const Frame& frame, Index v, const glm::dvec3& d) {
  const glm::dvec3 origin = frame.positions[v];
  for (const auto& t : topology.triangles) {
    if (t[0] == v || t[1] == v || t[2] == v) continue;
    const glm::dvec3 a = frame.positions[t[0]];
    const glm::dvec3 e1 = frame.positions[t[1]] - a, e2 = frame.positions[t[2]] - a;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-14) continue;
    const glm::dvec3 s = origin - a;
    const double u = glm::dot(s, p) / det;
    if (u < 0.0 || u > 1.0) continue;
    const glm::dvec3 q = glm::cross(s, e1);
    const double w = glm::dot(d, q) / det;
    if (w < 0.0 || u + w > 1.0) continue;
    if (glm::dot(e2, q) / det > 1e-9) return true;
  }
  return false;
}

TEST(ClothGenerators, ParsesKindNames) {
  for (ClothKind kind : kAllClothKinds) EXPECT_EQ(parse_cloth_kind(cloth_kind_name(kind)), kind);
  EXPECT_EQ(parse_cloth_kind("spiral"), ClothKind::Roll);
  EXPECT_EQ(parse_cloth_kind("tube"), ClothKind::Sleeve);
  EXPECT_FALSE(parse_cloth_kind("blanket").has_value());
  EXPECT_FALSE(parse_cloth_kind("").has_value());
}

TEST(ClothGenerators, SizesFollowTheResolution) {
  EXPECT_EQ(cloth_vertex_count(55), 3025u);
  EXPECT_EQ(cloth_vertex_count(173), 29929u);
  EXPECT_EQ(cloth_vertex_count(548), 300304u);
  for (ClothKind kind : kAllClothKinds)
    for (int n : {3, 10, 31}) {
      const ClothGenerator generator(kind, {n, 2, 24.0, 0});
      const MeshTopology& topology = generator.topology();
      EXPECT_EQ(topology.num_vertices, cloth_vertex_count(n));
      const std::size_t cells =
          kind == ClothKind::Sleeve ? std::size_t(n) * (n - 1) : std::size_t(n - 1) * (n - 1);
      EXPECT_EQ(topology.triangles.size(), 2 * cells) << name_of(kind);
      EXPECT_EQ(generator.frame(1).positions.size(), topology.num_vertices);
    }
}

TEST(ClothGenerators, RejectsBadParameters) {
  EXPECT_THROW(ClothGenerator(ClothKind::Curtain, {2, 60, 24.0, 0}), std::invalid_argument);
  EXPECT_THROW(ClothGenerator(ClothKind::Flag, {10, 0, 24.0, 0}), std::invalid_argument);
  EXPECT_THROW(ClothGenerator(ClothKind::Roll, {10, 5, 0.0, 0}), std::invalid_argument);
  EXPECT_THROW(ClothGenerator(ClothKind::Sleeve, {10, 5, std::nan(""), 0}), std::invalid_argument);
  const ClothGenerator generator(ClothKind::Curtain, {5, 3, 24.0, 0});
  EXPECT_THROW(generator.frame(3), std::out_of_range);
}

TEST(ClothGenerators, FrameTimesFollowTheFrameRate) {
  const ClothGenerator generator(ClothKind::Flag, {6, 5, 30.0, 0});
  for (std::size_t i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(generator.frame(i).time, double(i) / 30.0);
}

// Every frame of small and odd-sized grids (where the roll's spacing bound is tightest), several seeds.
TEST(ClothGenerators, NoSelfIntersectionsAtSmallResolutions) {
  for (ClothKind kind : kAllClothKinds)
    for (int n : {3, 4, 7, 12, 20})
      for (std::uint64_t seed : {0ull, 1ull, 2ull, 99ull}) {
        const ClothGenerator generator(kind, {n, 12, 24.0, seed});
        for (std::size_t f = 0; f < generator.num_frames(); ++f)
          EXPECT_TRUE(self_intersecting_faces(generator.topology(), generator.frame(f)).empty())
              << name_of(kind) << " resolution " << n << " seed " << seed << " frame " << f;
      }
}

TEST(ClothGenerators, NoSelfIntersectionsAtThreeThousandVertices) {
  for (ClothKind kind : kAllClothKinds)
    for (std::uint64_t seed : {0ull, 5ull}) {
      const ClothGenerator generator(kind, {55, 60, 24.0, seed});
      for (std::size_t f : {0, 17, 30, 44})
        EXPECT_TRUE(self_intersecting_faces(generator.topology(), generator.frame(f)).empty())
            << name_of(kind) << " seed " << seed << " frame " << f;
    }
}

// Folded, measurably: some pair of vertex normals is more than 115 degrees apart, and the ray along +n or
// -n from at least 5% of the vertices hits the cloth (a neighbouring fold occludes it).
TEST(ClothGenerators, AreTrulyFolded) {
  const double cos_limit = std::cos(115.0 * std::numbers::pi / 180.0);
  for (ClothKind kind : kAllClothKinds)
    for (std::uint64_t seed : {0ull, 1ull, 2ull}) {
      const ClothGenerator generator(kind, {24, 60, 24.0, seed});
      for (std::size_t f : {0, 15, 30}) {
        const Frame frame = generator.frame(f);
        const auto normals = vertex_normals(generator.topology(), frame);
        double min_dot = 1.0;
        for (std::size_t a = 0; a < normals.size(); ++a)
          for (std::size_t b = a + 1; b < normals.size(); ++b)
            min_dot = std::min(min_dot, glm::dot(normals[a], normals[b]));
        std::size_t occluded = 0;
        for (Index v = 0; v < generator.topology().num_vertices; ++v)
          if (ray_hits_cloth(generator.topology(), frame, v, normals[v]) ||
              ray_hits_cloth(generator.topology(), frame, v, -normals[v]))
            ++occluded;
        const std::string where =
            name_of(kind) + " seed " + std::to_string(seed) + " frame " + std::to_string(f);
        EXPECT_LT(min_dot, cos_limit) << where;
        EXPECT_GE(double(occluded), 0.05 * normals.size()) << where;
      }
    }
}

// Every edge is used at most once in each direction and, when by two faces, once in each direction;
// the boundary is the grid's rim (a sheet's 4 (n-1) edges, a tube's two rings of n); no face is degenerate.
TEST(ClothGenerators, AreConsistentlyWoundWithTheExpectedBoundary) {
  for (ClothKind kind : kAllClothKinds) {
    const int n = 9;
    const ClothGenerator generator(kind, {n, 8, 24.0, 3});
    std::map<std::pair<Index, Index>, int> directed;
    for (const auto& t : generator.topology().triangles)
      for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    std::size_t boundary = 0;
    for (const auto& [edge, count] : directed) {
      EXPECT_EQ(count, 1) << name_of(kind) << " edge " << edge.first << "-" << edge.second;
      if (!directed.count({edge.second, edge.first})) ++boundary;
    }
    EXPECT_EQ(boundary, kind == ClothKind::Sleeve ? std::size_t(2 * n) : std::size_t(4 * (n - 1)))
        << name_of(kind);
    for (std::size_t f = 0; f < generator.num_frames(); ++f) {
      const Frame frame = generator.frame(f);
      for (const auto& t : generator.topology().triangles) {
        const auto& p = frame.positions;
        EXPECT_GT(glm::length(glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]])), 0.0) << name_of(kind);
      }
    }
  }
}

TEST(ClothGenerators, AreDeterministicAndSeedsJitter) {
  for (ClothKind kind : kAllClothKinds) {
    const auto bytes = [&](std::uint64_t seed) {
      const GeneratedCloth cloth = generate_cloth(kind, {11, 4, 24.0, seed});
      std::string out;
      for (const auto& frame : cloth.frames)
        out.append(reinterpret_cast<const char*>(frame.positions.data()),
                   frame.positions.size() * sizeof(glm::dvec3));
      return out;
    };
    EXPECT_EQ(bytes(7), bytes(7)) << name_of(kind);
    EXPECT_EQ(bytes(0), bytes(0)) << name_of(kind);
    EXPECT_NE(bytes(7), bytes(8)) << name_of(kind);
    EXPECT_NE(bytes(0), bytes(1)) << name_of(kind);
  }
}

// The motion is smooth (no vertex jumps more than 10% of the cloth's size between frames at 60 frames),
// actually moves, and is one cycle: frame 0 and the middle frame differ.
TEST(ClothGenerators, MoveSmoothly) {
  for (ClothKind kind : kAllClothKinds) {
    const GeneratedCloth cloth = generate_cloth(kind, {16, 60, 24.0, 0});
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : cloth.frames[0].positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double size = glm::length(hi - lo);
    double max_step = 0.0, max_total = 0.0;
    for (std::size_t f = 1; f < cloth.frames.size(); ++f)
      for (std::size_t v = 0; v < cloth.frames[f].positions.size(); ++v) {
        max_step =
            std::max(max_step, glm::length(cloth.frames[f].positions[v] - cloth.frames[f - 1].positions[v]));
        max_total =
            std::max(max_total, glm::length(cloth.frames[f].positions[v] - cloth.frames[0].positions[v]));
      }
    EXPECT_LT(max_step, 0.1 * size) << name_of(kind);
    EXPECT_GT(max_total, 0.05 * size) << name_of(kind);
  }
}

TEST(GenerateCommand, WritesObjAndPc2) {
  test::TempDir dir;
  const auto obj = dir / "c.obj";
  const auto result = test::run_pleat("generate curtain -o " + obj.string() + " --resolution 10 --frames 3");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ASSERT_TRUE(std::filesystem::exists(obj));
  ASSERT_TRUE(std::filesystem::exists(dir / "c.pc2"));
  EXPECT_NE(result.output.find("c.obj"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("c.pc2"), std::string::npos) << result.output;
  EXPECT_EQ(std::filesystem::file_size(dir / "c.pc2"), 32u + 3u * 100u * 12u);
  const ObjMesh mesh = read_obj(obj);
  EXPECT_EQ(mesh.positions.size(), 100u);
  EXPECT_EQ(mesh.triangles.size(), 162u);
}

// Every kind round-trips through the files (float32 in the cache), still without self-intersections, and
// at the requested frame rate.
TEST(GenerateCommand, FilesReadBackToTheSameCloth) {
  test::TempDir dir;
  for (ClothKind kind : kAllClothKinds) {
    const auto obj = dir / (name_of(kind) + ".obj");
    const auto result = test::run_pleat("generate " + name_of(kind) + " -o " + obj.string() +
                                        " --resolution 12 --frames 4 --fps 30 --seed 4");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const GeneratedCloth expected = generate_cloth(kind, {12, 4, 30.0, 4});
    const ObjMesh mesh = read_obj(obj);
    ASSERT_EQ(mesh.triangles, expected.topology.triangles) << name_of(kind);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      EXPECT_EQ(mesh.positions[v], expected.frames[0].positions[v]) << name_of(kind) << " vertex " << v;
    const auto cache = open_pc2(dir / (name_of(kind) + ".pc2"));
    ASSERT_EQ(cache->num_frames(), 4u);
    for (std::size_t f = 0; f < 4; ++f) {
      EXPECT_NEAR(cache->frame_time(f), f / 30.0, 1e-6) << name_of(kind);
      Frame frame;
      frame.positions = cache->read_frame(f);
      ASSERT_EQ(frame.positions.size(), expected.frames[f].positions.size());
      for (std::size_t v = 0; v < frame.positions.size(); ++v)
        EXPECT_LT(glm::length(frame.positions[v] - expected.frames[f].positions[v]), 1e-6) << name_of(kind);
      EXPECT_TRUE(self_intersecting_faces(expected.topology, frame).empty())
          << name_of(kind) << " frame " << f;
    }
  }
}

TEST(GenerateCommand, RejectsUnknownKindAndNonObjOutput) {
  test::TempDir dir;
  auto result = test::run_pleat("generate blanket -o " + (dir / "b.obj").string());
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("unknown cloth kind 'blanket'"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("curtain"), std::string::npos) << result.output;  // lists the kinds
  result = test::run_pleat("generate flag -o " + (dir / "f.glb").string());
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find(".obj"), std::string::npos) << result.output;
  result = test::run_pleat("generate flag -o " + (dir / "f.obj").string() + " --resolution 2");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // nothing written on failure
}

TEST(GenerateCommand, HelpHasAnExample) {
  const auto result = test::run_pleat("generate --help");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.output.find("pleat generate curtain -o"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace pleat
