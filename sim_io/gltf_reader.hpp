// Reading glTF 2.0 (.gltf / .glb) cloth sequences through tinygltf (the writer: gltf_writer.hpp).
//
// Reading accepts three layouts of the default scene (node transforms applied, parents included):
//  1. Morph-target animation: the first animation with a `weights` channel on a mesh node with morph targets
//     gives one frame per keyframe of that channel (times from its input accessor; LINEAR, STEP and
//     CUBICSPLINE all sample to the keyframe values). positions = base + sum_k w_k * target_k. Other mesh
//     nodes are ignored; node transform animations are not applied.
//  2. Flipbook: two or more mesh nodes with the same connectivity (vertex count and triangles) are frames
//     shown one at a time. When every such node has a `scale` channel, frames are ordered by the first
//     keyframe at which the node's scale is non-zero, that keyframe is the frame's time and that non-zero
//     scale replaces the node's static one; otherwise frames follow the scene order at `scene_fps`.
//  3. Static: every mesh node merged into one mesh, one frame at time 0.
// Primitives of a mesh that share a POSITION accessor share vertices; primitive modes TRIANGLES,
// TRIANGLE_STRIP and TRIANGLE_FAN are triangulated. Primitives marked `"extras": {"pleat_side": "back"}`
// (the back-side copies written below) are skipped. Errors throw InputError naming the file and the
// accessor, mesh, node or frame: sparse accessors, accessors without a buffer view, quantized or draco
// compressed data (KHR_draco_mesh_compression, KHR_mesh_quantization, EXT_meshopt_compression, any other
// required extension that changes geometry), skins, POINTS/LINES primitives, out-of-range indices or
// accessor ranges, NaN/Inf positions, no mesh at all.
//
#pragma once

#include <filesystem>

#include "sim_io/mesh_sequence.hpp"

namespace pleat {

/// Loads a .gltf or .glb (see above); welds vertices that coincide in every frame.
MeshSequence load_gltf(const std::filesystem::path& path, double scene_fps = kDefaultSceneFps,
                       const LoadScan& scan = {});

}  // namespace pleat
