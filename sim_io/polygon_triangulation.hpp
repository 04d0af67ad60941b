// The triangles of one polygon of an input file (an OBJ `f` statement with four or more corners), in the
// polygon's own plane, over its own corners only (no new vertex), in its winding (docs/method.md §12).
//
// The plane: through the corners, normal to the polygon's Newell vector (the sum of its edges' cross
// products: the area vector of a planar polygon, the best-fit normal of a warped one); the corners are
// projected on it. Where the fan from the first corner tiles the projected polygon (each fan triangle turns
// the polygon's way and every corner lies on one side of the first edge's line: every convex polygon, so
// quads and convex n-gons split as every OBJ reader splits them), that fan. Otherwise (a concave polygon) the
// constrained Delaunay triangulation of the projected polygon (CGAL), its inside found by crossing its
// edges from the outside. A polygon with no proper triangulation over its corners — no area (collinear or
// repeated corners), or its projection crosses or touches itself — keeps the fan: its triangles are those the
// file's corners give, and the mesh checks (`pleat info`) count the degenerate ones.
// Decisions are exact predicates on the projected (rounded) corners. Cost: O(n) for a fanned polygon, O(n
// log n) expected for a triangulated one.
#pragma once

#include <array>
#include <cstddef>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

namespace pleat {

/// n - 2 triangles over the polygon's corners (0-based positions in `corners`, n = corners.size() >= 3),
/// each wound as the polygon is.
std::vector<std::array<std::size_t, 3>> triangulate_polygon(std::span<const glm::dvec3> corners);

}  // namespace pleat
