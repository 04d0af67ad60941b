// MeshSequence: one animated cloth as pleat holds it — fixed connectivity over welded vertices, frames read
// on demand (a sequence larger than memory streams), frame times, and the map back to the input's order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <glm/vec2.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat {

/// Scene rate used to turn frame numbers into seconds where a format stores no time (PC2 frames, numbered
/// OBJ sequences): Blender's default.
inline constexpr double kDefaultSceneFps = 24.0;

/// The range of coordinates pleat reads (MeshSequence checks every frame, docs/method.md §12). Beyond 2^53
/// doubles skip integers, which the lattice of planes counts in (the engines refuse the same,
/// static_core/mesh_validation.hpp); and pleat computes with products of several coordinate differences,
/// which must not underflow, so that A does not depend on the scene's unit: far below kMinExtent they do, and
/// every A would be 0.
inline constexpr double kMaxCoordinate =
    9007199254740992.0;                      ///< 2^53: |x|, |y|, |z| of every vertex and frame
inline constexpr double kMinExtent = 1e-30;  ///< the largest side of the box of every frame, at least

/// A source of per-frame positions in the input's vertex order (one implementation per file format).
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual std::size_t num_frames() const = 0;
  virtual double frame_time(std::size_t i) const = 0;  ///< seconds
  /// The number the source gives frame i (docs/method.md §12: the PC2 scene frame, the number in an OBJ
  /// sequence's file name, a time x scene fps); by default the index.
  virtual std::int64_t source_frame(std::size_t i) const { return std::int64_t(i); }
  /// Positions of frame i in input order; throws InputError naming the file and the frame on bad data.
  virtual std::vector<glm::dvec3> read_frame(std::size_t i) const = 0;
  /// The number of points every frame has as the source's header announces it, and where it says so (a
  /// byte offset), so that a mesh's vertex count is checked before any frame is read; points -1: none.
  struct Announced {
    std::int64_t points = -1;
    std::string place;
  };
  virtual Announced announced_points() const { return {}; }
};

/// A FrameSource over positions held in memory (static meshes, tests). frames[i] pairs with times[i].
std::unique_ptr<FrameSource> make_memory_source(std::vector<std::vector<glm::dvec3>> frames,
                                                std::vector<double> times);

/// How the loading pass (validation and welding, one read of every frame) is shared by cooperating processes
/// (cli/shared_load.hpp): each reads only the frames `range` gives it and `merge` combines what they found,
/// so no process reads the whole cache. The default reads every frame.
struct LoadScan {
  /// [first, last) of the frames this process reads, given the number of frames; empty: all of them.
  std::function<std::pair<std::size_t, std::size_t>(std::size_t num_frames)> range;
  /// Sees each frame this process reads, in input order, after it was validated (e.g. to fingerprint it).
  std::function<void(std::size_t frame, const std::vector<glm::dvec3>& positions)> on_frame;
  /// Called once by every process after its scan, with its weld classes (labels numbered by first appearance
  /// in input order; equal labels: coincide in every frame it read) and what its scan threw (null if
  /// nothing). Must leave the classes over all frames, or throw the error of the lowest frame any process
  /// met. A collective operation: every process calls it, whatever happened.
  std::function<void(std::vector<Index>& classes, std::exception_ptr error)> merge;
  /// Called once by every process after a merge that threw nothing, with the box of the frames it read
  /// (MeshSequence::bounds); must leave the box of all frames. A collective operation, like merge.
  std::function<void(Bounds& bounds)> merge_bounds;
};

/// What the input says about its surface besides positions, per corner of MeshSequence::input_triangles()
/// (3 per triangle, in order), for outputs on the artist's mesh (gltf_writer.hpp, the input layout). Each is
/// empty where the input does not give it at every corner.
struct SurfaceAttributes {
  std::vector<glm::vec2> texcoords;  ///< OBJ vt, glTF TEXCOORD_0; glTF's convention (v down from the top)
  std::vector<glm::vec3> normals;    ///< OBJ vn, glTF NORMAL, as given (of the input's own pose)
};

class MeshSequence {
 public:
  /// Welds input vertices whose positions coincide exactly in every frame (glTF exporters split them at UV
  /// seams): one streaming pass over all frames, which also validates each of them (vertex count, finite
  /// coordinates within kMaxCoordinate, through the source), that the mesh spans kMinExtent (the box of the
  /// vertices the triangles use, over every frame) and that times are finite and strictly increasing. O(V)
  /// memory, O(V) expected time per frame. Throws InputError naming `name` and the frame. `scan` shares that
  /// pass between processes (LoadScan). `surface`: per corner of input_triangles, or empty
  /// (std::invalid_argument on another size).
  MeshSequence(std::string name, std::vector<Triangle> input_triangles, Index num_input_vertices,
               std::unique_ptr<FrameSource> frames, const LoadScan& scan = {},
               SurfaceAttributes surface = {});
  /// An in-memory sequence (generators, tests): no welding.
  MeshSequence(std::string name, MeshTopology topology, std::vector<Frame> frames);

  const std::string& name() const;
  const MeshTopology& topology() const;
  std::size_t num_frames() const;
  double frame_rate() const;         ///< frames per second; 0 for a single frame
  Frame frame(std::size_t i) const;  ///< welded positions of frame i

  Index num_input_vertices() const;
  const std::vector<Index>& welded_of_input() const;  ///< input vertex -> welded vertex
  std::size_t welded_duplicates() const;              ///< input vertices merged into another

  /// The box of every frame's positions of the vertices the triangles use: what a slicing plan must cover
  /// so that every frame is cut by the same world-anchored planes (static_core/slicing_plan.hpp).
  const Bounds& bounds() const;
  double frame_time(std::size_t i) const;  ///< seconds, strictly increasing
  double duration() const;                 ///< last frame time - first frame time
  /// The frame's number in the source (FrameSource::source_frame): what the CSV's source_frame column,
  /// render file names and glb times say; frame(i) is still addressed by its 0-based index i.
  std::int64_t source_frame(std::size_t i) const;
  /// Positions of frame i in the input's vertex order (before welding).
  std::vector<glm::dvec3> input_positions(std::size_t i) const;
  /// The input's triangles over input vertices (after polygon triangulation, before welding).
  const std::vector<Triangle>& input_triangles() const;
  /// Input triangles left out of topology(): those with a repeated corner after welding, and repeats of an
  /// earlier triangle on the same three welded vertices in either winding (e.g. the reversed back-side
  /// copies of a double-sided export). topology().triangles keeps the others in input order.
  std::size_t removed_faces() const;
  /// The input's UVs and normals per corner of input_triangles() (SurfaceAttributes).
  const SurfaceAttributes& surface() const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> m_impl;  // private: cheap copies of an immutable model
};

}  // namespace pleat
