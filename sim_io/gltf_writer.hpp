// Writing the shaded sequence as a flipbook .glb that plays in three.js and imports into Blender (the reader:
// gltf_reader.hpp, which reads these files back).
//
// write_shaded_glb / ShadedGlbWriter use a flipbook, not COLOR_0 morph targets: Blender's glTF
// importer does not import COLOR_0 morph targets, and three.js would need custom shader work for them. Each
// frame is one node + mesh with its own POSITION and COLOR_0; a STEP `scale` channel per node switches it
// between 0 and 1 so exactly one frame is visible at a time, which both three.js and Blender play natively
// (node 0 has static scale 1, the others 0, so static viewers show the first frame). Both cloth sides are
// shaded: each frame mesh has a front primitive (the triangles in input winding, front colours) and a back
// primitive (the same triangles reversed, back colours, same POSITION accessor) under one single-sided
// material, so back-face culling shows each side its own shading; a doubleSided material could only show
// one colour on both sides. The material is KHR_materials_unlit (the colours are already lit) with a
// rough, non-metallic white fallback. COLOR_0 holds linear float RGB converted from the given sRGB. With
// visibility (ShadedGlbWriter's `with_visibility`), each primitive also carries its side's cones as two
// application-specific attributes (glTF 2.0 §3.7.2.1: names start with an underscore): _SKY_VISIBILITY
// (SCALAR float: A) and _BENT_CONE (VEC4 float: the unit bent normal, and the cosine of the half-angle of the
// circular cone with the same solid angle as the visible set), for engines that light the cloth themselves.
// Each frame's data is contiguous in the binary chunk with a buffer view per element type.
// The reader above accepts this layout, so a written glb reads back as the same sequence (float32 positions).
// Checked by hand on written files: Khronos glTF-Validator 2.0.0-dev.3.10 reports no issue; three.js r160
// GLTFLoader + AnimationMixer shows exactly one frame at a time (MeshBasicMaterial with vertex colours,
// FrontSide); Blender 3.4 imports one object per frame with a "Col" colour attribute, CONSTANT scale keys
// and an emission (unlit) material.
#pragma once

#include <cstddef>
#include <filesystem>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "sim_io/up_axis.hpp"
#include "support/atomic_file.hpp"

namespace pleat {

/// One side's visibility per welded vertex, as the glb's _SKY_VISIBILITY and _BENT_CONE attributes.
struct SideVisibility {
  std::vector<float> sky_visibility;  ///< A in [0, 1]
  std::vector<glm::vec4>
      bent_cone;  ///< unit bent normal (xyz), cosine of the equal-solid-angle half-angle (w)
};

/// What a shaded glb's frame meshes are made of (docs/method.md §12).
enum class GlbLayout {
  /// The welded vertices, a front primitive and a back primitive (reversed triangles) with their side's
  /// COLOR_0, _SKY_VISIBILITY and _BENT_CONE, under a single-sided material: what `pleat view` reads.
  Sides,
  /// The artist's mesh: the input's vertices in its order and its triangles in one primitive, its UVs
  /// (TEXCOORD_0) and normals (NORMAL, as given) where it has them, front colour in COLOR_0 and back in
  /// COLOR_1, _SKY_VISIBILITY_FRONT/_BACK and _BENT_CONE_FRONT/_BACK, a double-sided material. Where the
  /// input's corners give one vertex several UVs or normals, copies of it follow the input's vertices
  /// (mesh extras `pleat_seam_copies` lists the input vertex of each).
  Input,
};

/// Exact float bounds of a frame's positions as a glb stores them (its POSITION accessor's min and max).
struct PositionBounds {
  glm::vec3 lo, hi;
};
PositionBounds position_bounds(const Frame& frame);

/// Streams a shaded flipbook .glb: the constructor reads the chosen frames' positions once (for the
/// accessor bounds) and writes the JSON; add_frame() then appends one frame's data in order; finish() commits
/// the file atomically. Destroyed before finish(), nothing is left on disk. Frame j plays from its time
/// (MeshSequence::frame_time) to the next frame's; the last one for 1 / fps.
class ShadedGlbWriter {
 public:
  /// `with_visibility`: every add_frame() brings both sides' visibility, written as vertex attributes.
  ShadedGlbWriter(const std::filesystem::path& path, const MeshSequence& sequence,
                  std::vector<std::size_t> frames, double fps, bool with_visibility = false,
                  GlbLayout layout = GlbLayout::Sides);
  /// The same with each frame's position_bounds() given (frame j: bounds[j], in the input's axes), so the
  /// constructor reads no frame: for a writer whose frames' positions come from elsewhere (other processes,
  /// cli/run_chunks.hpp). `turn` turns every position, normal and bent normal written (an input whose up is
  /// not +Y stood up in glTF's Y-up space: sim_io/up_axis.hpp).
  ShadedGlbWriter(const std::filesystem::path& path, const MeshSequence& sequence,
                  std::vector<std::size_t> frames, double fps, bool with_visibility,
                  const std::vector<PositionBounds>& bounds, GlbLayout layout = GlbLayout::Sides,
                  const AxisTurn& turn = {});
  ~ShadedGlbWriter();
  ShadedGlbWriter(const ShadedGlbWriter&) = delete;
  ShadedGlbWriter& operator=(const ShadedGlbWriter&) = delete;

  /// Colours of the next frame, one sRGB colour (components in [0,1], clamped) per welded vertex and side.
  void add_frame(const std::vector<glm::vec3>& front_srgb, const std::vector<glm::vec3>& back_srgb);
  /// The same with both sides' visibility (the writer must have been made `with_visibility`).
  void add_frame(const std::vector<glm::vec3>& front_srgb, const std::vector<glm::vec3>& back_srgb,
                 const SideVisibility& front, const SideVisibility& back);
  /// The same with the frame's positions as stored (float, per welded vertex) given instead of read.
  void add_frame(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& front_srgb,
                 const std::vector<glm::vec3>& back_srgb, const SideVisibility& front,
                 const SideVisibility& back);
  /// Writes the rest of the file and closes it (a failed write throws here, naming the file and why).
  void close();
  /// close(), then renames the file into place (with other outputs: inside one CommitWindow).
  void commit();
  /// commit().
  void finish();

 private:
  const MeshSequence& m_sequence;
  std::vector<std::size_t> m_frames;
  bool m_with_visibility = false;
  std::vector<Index> m_welded_of_vertex;  // the input layout's vertices' welded vertices; empty: the welded
  AxisTurn m_turn;
  std::size_t m_next = 0;
  std::size_t m_tail_bytes = 0;  // animation data written by finish()
  std::vector<unsigned char> m_tail;
  bool m_closed = false;
  AtomicFile m_file;
};

/// One-shot form: front_srgb[j] / back_srgb[j] colour frames[j] (per welded vertex).
void write_shaded_glb(const std::filesystem::path& path, const MeshSequence& sequence,
                      const std::vector<std::size_t>& frames,
                      const std::vector<std::vector<glm::vec3>>& front_srgb,
                      const std::vector<std::vector<glm::vec3>>& back_srgb, double fps);

}  // namespace pleat
