// Wavefront OBJ: reads `v`, `vt`, `vn` and `f` statements (polygons of four or more corners triangulated in
// their plane over their own corners, sim_io/polygon_triangulation.hpp) and writes a triangle mesh with
// shortest round-tripping decimal coordinates.
//
// Reading is one pass over the lines, O(size of file). Face corners may be `i`, `i/t`, `i//n` or `i/t/n`;
// negative indices count back from the last element defined so far (OBJ's relative form). Every other
// statement (o, g, s, usemtl, mtllib, l, p, ...) is skipped, and so is a UTF-8 byte-order mark at the start
// of the file. Bad input throws InputError naming the
// file and the line: non-numeric or non-finite coordinates, index 0 or out of range, a face with fewer than
// three corners, an empty mesh (no vertices or no faces); the same for vt/vn values and indices.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "static_core/mesh.hpp"

namespace pleat {

/// An OBJ as read: positions in file order, its polygons and their triangles.
struct ObjMesh {
  std::vector<glm::dvec3> positions;
  std::vector<Triangle> triangles;  ///< every polygon's, in file order (triangulate_polygon of its corners)
  std::size_t num_polygons = 0;     ///< `f` statements
  /// The polygons as the file gives them: polygon p's corners (0-based vertex indices) are polygon_corners[k]
  /// for k from polygon_starts[p] up to polygon_starts[p + 1] (num_polygons + 1 starts).
  std::vector<Index> polygon_corners;
  std::vector<std::size_t> polygon_starts;
  std::vector<glm::dvec2> texcoords;  ///< `vt` (u, v) in file order
  std::vector<glm::dvec3> normals;    ///< `vn` in file order
  /// Per triangle corner (3 per triangle, in order): the 0-based index into texcoords / normals, or -1 where
  /// the corner names none.
  std::vector<std::int64_t> corner_texcoords, corner_normals;
};

/// Reads `path`. Throws InputError (file, "line N") on malformed input, InputError (file) when the file is
/// missing or unreadable or holds no vertex or no face.
ObjMesh read_obj(const std::filesystem::path& path);
/// The same without the triangles (and their corners' attributes): what a later frame of an OBJ sequence
/// needs, whose polygons must be the first frame's and are split as the first frame's are.
ObjMesh read_obj_polygons(const std::filesystem::path& path);

/// The mesh's UVs and normals per triangle corner (texcoords flipped to glTF's v-down convention); each
/// empty unless every corner names one.
SurfaceAttributes surface_of(const ObjMesh& mesh);

/// Writes `v` lines (shortest decimal form that reads back to the same double) and 1-based `f` lines,
/// atomically (temporary file + rename). Throws std::invalid_argument when positions.size() differs from
/// topology.num_vertices or a triangle index is out of range, std::runtime_error on I/O failure.
void write_obj(const std::filesystem::path& path, const MeshTopology& topology,
               const std::vector<glm::dvec3>& positions);

}  // namespace pleat
