// Small meshes with known visibility: a flat sheet, an icosphere, a V-fold, a closed box; and rigid
// transforms.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "static_core/mesh.hpp"

namespace pleat::test {

struct TestMesh {
  MeshTopology topology;
  Frame frame;
  Index marked_vertex = 0;  ///< a vertex of interest (the V-fold's bottom centre)
};

/// A flat nx x ny grid in the plane z = 0, `spacing` apart from `origin`, counter-clockwise: normals +z.
TestMesh flat_sheet(int nx, int ny, double spacing = 1.0, glm::dvec2 origin = {0.0, 0.0});
/// An icosphere of unit radius, `subdivisions` times subdivided, outward normals.
TestMesh icosphere(int subdivisions);
/// Two planes meeting along the x axis, opening towards +z with half-angle `alpha` from the vertical:
/// nx vertices along x over [-length/2, length/2], n_arm vertices per arm over `arm` (the bottom row is
/// shared). Front side is the inside of the V. marked_vertex: the bottom vertex at x = 0.
TestMesh v_fold(double alpha, int nx, int n_arm, double length, double arm);
/// The axis-aligned box [lo, hi]: 8 vertices (lo.z's face first, counter-clockwise from lo seen from +z), 12
/// triangles wound outward (normals out of the solid): a closed occluder.
TestMesh closed_box(const glm::dvec3& lo, const glm::dvec3& hi);
/// Rotates by `angle` about `axis`, then translates.
void rigid_transform(TestMesh& mesh, const glm::dvec3& axis, double angle, const glm::dvec3& translation);

}  // namespace pleat::test
