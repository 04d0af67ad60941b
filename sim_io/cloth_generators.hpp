// Analytic animated cloth for tests and benchmarks: deep folds, any size, and no self-intersection by
// construction (each kind below says why), so pleat's algorithm and its oracles can run on them at 3k, 30k
// or 300k vertices without a simulator.
//
// Every kind is a regular grid of resolution x resolution vertices (a sheet, or a tube closed around its
// axis) with fixed connectivity, consistently wound: triangle (a, b, c) of grid cell (i, j) is
// (v(i,j), v(i+1,j), v(i+1,j+1)) and (v(i,j), v(i+1,j+1), v(i,j+1)), vertex v(i,j) = j * columns + i.
// Frame f is at time f / fps; the motion is one cycle over the sequence (frames / fps seconds), so it loops.
// A seed of 0 gives the nominal shapes; any other seed jitters amplitudes, phases and proportions
// (deterministically: splitmix64, the same bytes on every platform). Cost: O(resolution^2) per frame.
//
// Why each kind cannot self-intersect (for the piecewise-linear mesh, not just the smooth surface):
//  - Curtain, Flag — graphs over the plane z = 0. Column i has one x_i(t), strictly increasing in i; in each
//    column y_ij(t) is strictly monotone in j; z is arbitrary. So the grid projects onto the plane as
//    strips between vertical lines, each cut into trapezoids by non-crossing segments, and each trapezoid
//    (convex: two vertical sides) into two triangles: a planar triangulation. The mesh is the graph of a
//    piecewise-linear function over it: distinct points of the plane carry distinct points of the mesh, and
//    two triangles meet only above a shared edge or vertex of the triangulation, i.e. in a shared edge or
//    vertex of the mesh.
//  - Sleeve — a graph in cylindrical coordinates about the y axis: column i sits at angle 2*pi*i/columns
//    (at least 3 columns, so every cell's wedge is convex), row j at height y_j(t) strictly monotone in j
//    and the same for every column, radius r_ij(t) > 0 arbitrary. Cell (i, j) lies in the convex set
//    wedge_i x slab_j; those sets meet only on their boundary half-planes and planes, and a cell's triangle
//    meets such a boundary only in the mesh edge or vertex lying on it (its other corners are strictly
//    inside), nor the axis (all corners have r > 0 in a wedge narrower than pi). Within a cell the two
//    triangles share their diagonal; if the four corners are coplanar they form the convex quadrilateral
//    cut out of that plane by the cell's four boundary planes, so the far corners lie on opposite sides
//    of the diagonal and the triangles meet only along it.
//  - Roll — a cylinder over a simple curve: every row (z = const) has the same cross-section polyline, so
//    the mesh is embedded iff the polyline is simple. The rolled part samples an Archimedean spiral
//    r = b*phi (gap 2*pi*b between turns) from inner radius c, the rest lies on the spiral's tangent at
//    the outer end, which moves away from the origin (|P + l T|^2 = r^2 + 2 l r r' + l^2 |T|^2 grows),
//    so it stays outside the disk holding the spiral. Consecutive samples are ds = L/(columns-1) apart
//    along the sheet, so one chord spans an angle D <= ds/c <= pi/2 about the origin and keeps a distance
//    in [r_start cos(D/2), r_end]; the generator takes gap >= ds/2 and c > ds^2/(4 gap), which keeps every
//    chord of one turn strictly outside every chord of the turn inside it in each direction (the gap,
//    2*pi*b minus twice the radial growth over one chord, exceeds the sagitta ds^2/(8c)).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat {

enum class ClothKind { Curtain, Roll, Flag, Sleeve };
inline constexpr std::array<ClothKind, 4> kAllClothKinds = {ClothKind::Curtain, ClothKind::Roll,
                                                            ClothKind::Flag, ClothKind::Sleeve};

/// "curtain", "roll" (or "spiral"), "flag", "sleeve" (or "tube"); case-sensitive; nullopt otherwise.
std::optional<ClothKind> parse_cloth_kind(std::string_view name);
std::string_view cloth_kind_name(ClothKind kind);

struct GeneratorParams {
  int resolution = 40;     ///< grid of resolution x resolution vertices; at least 3
  int frames = 60;         ///< at least 1
  double fps = 24.0;       ///< frames per second, > 0
  std::uint64_t seed = 0;  ///< 0: nominal shapes; otherwise jittered parameters
};

/// Number of vertices for a resolution (resolution^2 for every kind); e.g. 55 -> 3,025, 173 -> 29,929,
/// 548 -> 300,304.
Index cloth_vertex_count(int resolution);

/// A generator: the fixed topology and any frame on demand (streams large sequences).
class ClothGenerator {
 public:
  /// The kind's proportions after jitter (lengths in metres; what each field means per kind is in
  /// cloth_generators.cpp). Exposed for tests and documentation; fixed at construction.
  struct Shape {
    double length = 0, width = 0;             // sheet or tube extent
    double count = 0;                         // pleats, waves or folds
    double depth_lo = 0, depth_hi = 0;        // fold depth at the start and the middle of the cycle
    double phase = 0, phase2 = 0, tilt = 0;   // radians
    double sway = 0, squash = 0, shrink = 0;  // secondary motions
    double cycles = 0;                        // flag: whole wave cycles per sequence
    double gap = 0, inner_radius = 0;         // roll: distance between turns, innermost radius
  };

  /// Throws std::invalid_argument (naming the parameter) when params are out of range.
  ClothGenerator(ClothKind kind, const GeneratorParams& params);

  ClothKind kind() const { return m_kind; }
  const GeneratorParams& params() const { return m_params; }
  const MeshTopology& topology() const { return m_topology; }
  std::size_t num_frames() const { return static_cast<std::size_t>(m_params.frames); }
  /// Positions of frame i (time i / fps). Throws std::out_of_range for i >= num_frames().
  Frame frame(std::size_t i) const;
  const Shape& shape() const { return m_shape; }

 private:
  ClothKind m_kind;
  GeneratorParams m_params;
  MeshTopology m_topology;
  Shape m_shape;
};

/// A whole generated sequence in memory (wrap it as MeshSequence(name, topology, frames) if needed).
struct GeneratedCloth {
  std::string name;  ///< e.g. "curtain"
  MeshTopology topology;
  std::vector<Frame> frames;
  double fps = 24.0;
};

GeneratedCloth generate_cloth(ClothKind kind, const GeneratorParams& params);

}  // namespace pleat
