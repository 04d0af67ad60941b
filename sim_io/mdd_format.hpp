// MDD point caches (LightWave / Blender "MDD"), big-endian, docs/method.md §12:
//   int32 frameCount, int32 vertCount, frameCount x float32 times (seconds),
//   then frameCount x vertCount x float32[3].
//
// Unlike PC2, MDD stores each frame's time in seconds, so frame times come straight from the file (they
// must be finite and strictly increasing). Opening validates the header, the size and the times (O(frames));
// read_frame(i) reads one frame on demand (O(vertCount)).
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "sim_io/mesh_sequence.hpp"

namespace pleat {

struct MddHeader {
  std::int32_t num_frames = 0;
  std::int32_t num_points = 0;
  std::vector<double> times;  ///< seconds, one per frame
};

/// Reads and validates the header, the times and that the file size matches the counts. Throws InputError
/// naming the file and the byte offset (truncated, oversized, non-positive counts, bad times).
MddHeader read_mdd_header(const std::filesystem::path& path);

/// A FrameSource over an MDD file. read_frame(i) throws InputError naming the file, the frame and the
/// vertex of a NaN/Inf coordinate. Frame i's source frame number is its time x scene_fps, rounded.
std::unique_ptr<FrameSource> open_mdd(const std::filesystem::path& path, double scene_fps = kDefaultSceneFps);

/// Writes frames (each the same number of points) with their times (seconds), atomically. Throws
/// std::invalid_argument on empty or ragged frames or a times/frames size mismatch.
void write_mdd(const std::filesystem::path& path, const std::vector<std::vector<glm::dvec3>>& frames,
               const std::vector<double>& times);

}  // namespace pleat
