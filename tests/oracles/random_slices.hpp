// Random slices for property tests: sets of non-crossing planar chains (closed and open, nested into holes,
// dangling, snapped to a coarse grid for collinear and duplicate points), and slices of random height-field
// meshes by random planes, some placed exactly through mesh vertices.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <random>
#include <vector>

#include "static_core/mesh.hpp"
#include "static_core/mesh_slicer.hpp"

namespace pleat::test {

/// A Slice made of explicit chains (each a list of points; closed chains repeat no point).
Slice make_slice(const std::vector<std::vector<glm::dvec2>>& chains, const std::vector<bool>& closed);

/// Random non-crossing chains: star-shaped loops, some opened or cut into dangling pieces, some nested.
Slice random_chain_slice(std::mt19937_64& rng);

/// A random folded height field z = f(x, y) over an n x n grid (cannot self-intersect).
struct RandomSurface {
  MeshTopology topology;
  Frame frame;
};
RandomSurface random_height_field(std::mt19937_64& rng, int n);

/// A random plane through the surface; with probability 1/3 exactly through one of its vertices.
SlicingPlane random_plane_through(std::mt19937_64& rng, const Frame& frame);

/// `count` slices of one random folded height field (6 to 15 vertices a side, from `seed`) by random planes
/// through it (random_plane_through).
std::vector<Slice> random_surface_slices(std::uint64_t seed, int count);

}  // namespace pleat::test
