// The scene a cloth was simulated in: occluders (bodies, tables, any triangle list; static, or animated with
// the cloth's frames) and infinite ground planes, appended to the cloth so that the engines slice them with
// it. They block sight lines and receive no cones (MeshTopology::num_occluder_vertices; docs/method.md §1).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim_io/mesh_sequence.hpp"

namespace pleat {

/// An occluder file as the command line names it: "PATH" (any input pleat reads: .obj, an OBJ sequence,
/// .gltf/.glb) or "PATH,cache=CACHE" (an .obj with its .pc2/.mdd cache).
struct OccluderSpec {
  std::string path;
  std::string cache;
};
/// Parses "PATH[,cache=CACHE]". Throws std::invalid_argument naming the text.
OccluderSpec parse_occluder_spec(std::string_view text);

/// The infinite plane {x : x[axis] == height}, the boundary of a solid on its -axis side (a floor), or on its
/// +axis side when `up` is -1 (a ceiling, a Y-down scene's floor).
struct GroundPlane {
  int axis = 1;
  double height = 0.0;
  double up = 1.0;
};
/// Parses "AXIS=VALUE" or "-AXIS=VALUE" (AXIS x, y or z; "-": the solid on the +axis side). Throws
/// std::invalid_argument naming the text.
GroundPlane parse_ground_plane(std::string_view text);

class Scene {
 public:
  /// The cloth alone.
  explicit Scene(const MeshSequence& cloth);
  /// The cloth with its occluders, each read with load_sequence: one of a single frame holds for every
  /// frame; an animated one must run at the cloth's rate and is paired with the cloth frame by frame by
  /// source frame number (MeshSequence::source_frame: a PC2 starting at scene frame 50 pairs its sample 0
  /// with the cloth's frame numbered 50), so it must hold every number the cloth holds (it may hold more). A
  /// ground plane is an occluding plane of the topology (MeshTopology::planes), which the cone engines apply
  /// exactly; for ray casting and rendering it stands as a square centred under the cloth whose side is 100
  /// diagonals of the box of all its frames (MeshSequence::bounds): seen from a cloth vertex at height h
  /// above it, its edge is at most h / (50 diagonals) rad above the horizon, a sliver whose cosine-weighted
  /// share of the hemisphere is below (h / 50 diagonals)^2. (Larger would stretch the relative offsets of ray
  /// casting, shading/embree_scene.hpp.) Throws InputError naming the occluder's file on anything unreadable
  /// or mismatched. `cloth` must outlive the scene.
  ///
  /// The contact tolerance (MeshTopology::contact_tolerance, docs/method.md §6.2) is `contact_tolerance`
  /// when given (finite, >= 0; else InputError), else half the mean edge length of the cloth's first frame.
  Scene(const MeshSequence& cloth, const std::vector<OccluderSpec>& occluders,
        const std::vector<GroundPlane>& grounds, std::optional<double> contact_tolerance = std::nullopt);
  /// An occluder already loaded (or made in memory), and the name its errors give.
  struct LoadedOccluder {
    std::string name;
    MeshSequence mesh;
  };
  /// The same with occluders already loaded: the same checks (frame rate and numbers), naming each by its
  /// name.
  static Scene with_loaded(const MeshSequence& cloth, std::vector<LoadedOccluder> occluders,
                           const std::vector<GroundPlane>& grounds,
                           std::optional<double> contact_tolerance = std::nullopt);

  /// The cloth's topology, then every occluder's triangles over its vertices, numbered after the cloth's.
  const MeshTopology& topology() const { return m_topology; }
  /// Frame i of the cloth (MeshSequence::frame), then the occluders' positions at that frame.
  Frame frame(std::size_t i) const { return with_occluders(i, m_cloth->frame(i)); }
  /// `cloth`, frame i of the cloth already read, with the occluders' positions at that frame appended.
  Frame with_occluders(std::size_t i, Frame cloth) const;
  std::size_t num_occluders() const { return m_occluders.size() + m_grounds.size(); }
  /// The ground planes' corners: the last vertices of topology() and of a frame with occluders.
  std::size_t num_ground_vertices() const { return m_grounds.size(); }

 private:
  void add(std::vector<LoadedOccluder> occluders, const std::vector<GroundPlane>& grounds,
           std::optional<double> contact_tolerance);
  struct Occluder {
    MeshSequence mesh;
    std::vector<glm::dvec3> still;      ///< the positions of an occluder of one frame (else empty)
    std::vector<std::size_t> frame_of;  ///< animated: its frame paired with each of the cloth's
  };
  const MeshSequence* m_cloth;
  std::vector<Occluder> m_occluders;
  std::vector<glm::dvec3> m_grounds;  ///< four corners per ground plane
  MeshTopology m_topology;
};

}  // namespace pleat
