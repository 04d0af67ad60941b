// load_sequence: a cloth sequence from its file(s), whatever the format; the one entry the CLI, the tests and
// the benchmarks use (the readers of each format are sim_io/*_format.hpp, gltf_reader.hpp, obj_sequence.hpp).
#pragma once

#include <filesystem>

#include "sim_io/mesh_sequence.hpp"

namespace pleat {

/// Opens INPUT as pleat understands it:
///   .obj (+ optional cache .pc2 / .mdd), a numbered OBJ sequence (printf pattern like "frames/f_%04d.obj",
///   or a directory of .obj files in name order), .gltf / .glb (static, morph-target weights animation, or
///   a scene with one node per frame).
/// Throws InputError on anything malformed. Loading validates every frame once (one streaming pass, which
/// also finds the welding); frames are then re-read on demand.
MeshSequence load_sequence(const std::filesystem::path& input, const std::filesystem::path& cache = {});

struct LoadOptions {
  double scene_fps = kDefaultSceneFps;  ///< seconds per frame for formats that store frame numbers only
  LoadScan scan;                        ///< which frames this process validates and welds over
};
MeshSequence load_sequence(const std::filesystem::path& input, const std::filesystem::path& cache,
                           const LoadOptions& options);

}  // namespace pleat
