// Wavefront OBJ: reads `v` and `f` statements (polygons fan-triangulated; `vt`/`vn` ignored) and writes
// a triangle mesh with shortest round-tripping decimal coordinates.
//
// Reading is one pass over the lines, O(size of file). Face corners may be `i`, `i/t`, `i//n` or `i/t/n`;
// negative indices count back from the last vertex defined so far (OBJ's relative form). Every other
// statement (o, g, s, usemtl, mtllib, vt, vn, l, p, ...) is skipped. Bad input throws InputError naming the
// file and the line: non-numeric or non-finite coordinates, index 0 or out of range, a face with fewer than
// three corners, an empty mesh (no vertices or no faces).
#pragma once

#include <cstddef>
#include <filesystem>
#include <glm/vec3.hpp>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat {

/// An OBJ as read: positions in file order and the triangles of its fan-triangulated polygons.
struct ObjMesh {
  std::vector<glm::dvec3> positions;
  std::vector<Triangle> triangles;
  std::size_t num_polygons = 0;  ///< `f` statements before triangulation
};

/// Reads `path`. Throws InputError (file, "line N") on malformed input, InputError (file) when the file is
/// missing or unreadable or holds no vertex or no face.
ObjMesh read_obj(const std::filesystem::path& path);

/// Writes `v` lines (shortest decimal form that reads back to the same double) and 1-based `f` lines,
/// atomically (temporary file + rename). Throws std::invalid_argument when positions.size() differs from
/// topology.num_vertices or a triangle index is out of range, std::runtime_error on I/O failure.
void write_obj(const std::filesystem::path& path, const MeshTopology& topology,
               const std::vector<glm::dvec3>& positions);

}  // namespace pleat
