// Which way is up in the input, and how a glb written from it stands up in glTF's +Y-up space.
//
// glTF is Y-up; Blender, Houdini's defaults aside, and the add-on's world positions are Z-up. An input whose
// up is an axis (±x, ±y, ±z) is turned by the rotation taking that axis to +Y (Z-up: (x, y, z) ->
// (x, z, -y), as Blender's glTF exporter does, and its importer undoes), a signed permutation of the
// coordinates: exact in floats, so bounds and winding carry over. `pleat shade --up` chooses it; `auto`
// takes the ground plane's side (--ground), else +Y (glTF's, and what Blender's OBJ and PC2 exporters write
// by default); the way the cloth falls (gravity) only warns when it says otherwise.
#pragma once

#include <array>
#include <glm/vec3.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "sim_io/scene.hpp"

namespace pleat {

/// A proper rotation that permutes axes with signs: out[k] = sign[k] * in[from[k]]. Default: identity.
struct AxisTurn {
  std::array<int, 3> from{0, 1, 2};
  std::array<float, 3> sign{1.0f, 1.0f, 1.0f};

  bool identity() const {
    return from == std::array<int, 3>{0, 1, 2} && sign == std::array<float, 3>{1, 1, 1};
  }
  glm::vec3 operator()(const glm::vec3& v) const {
    return {sign[0] * v[from[0]], sign[1] * v[from[1]], sign[2] * v[from[2]]};
  }
  /// The turned box of [lo, hi] (exact: coordinates move and change sign).
  void bounds(glm::vec3& lo, glm::vec3& hi) const;
};

/// The rotation taking the unit axis `axis` (0, 1, 2 for x, y, z) with `sign` (+1, -1) to +Y.
AxisTurn turn_to_y_up(int axis, int sign);

/// The input's up as chosen: a unit vector, the axis turn for the glb (identity when `up` is not an axis),
/// where it came from ("--up", "--ground z=0", "the default"), and a warning ("" if none) when the ground
/// or the cloth's fall says otherwise.
struct UpChoice {
  glm::dvec3 up{0.0, 1.0, 0.0};
  AxisTurn turn;
  std::string name;  ///< "+z", "-y", ... or the vector as given
  std::string source;
  std::string warning;
};

/// The cloth's fall between its first and last frames: the axis and sign against which its centroid moved,
/// when it moved by at least 5% of the first frame's box diagonal and at least twice as far along that axis
/// as along any other; {-1, 0} otherwise. Reads two frames.
std::array<int, 2> fall_direction(const MeshSequence& cloth);

/// `text`: "auto", an axis ("x", "y", "z", "-x", ...) or a vector "X,Y,Z" (the camera's up only, unless it
/// is an axis). `ground`: the --ground text ("" if none). Throws std::invalid_argument naming `text`.
UpChoice choose_up(std::string_view text, std::string_view ground, const MeshSequence& cloth);

}  // namespace pleat
