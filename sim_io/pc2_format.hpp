// PC2 point caches (3ds Max / Blender "POINTCACHE2"), little-endian, docs/method.md §12:
//   char[12] "POINTCACHE2\0", int32 version = 1, int32 numPoints, float32 startFrame, float32 sampleRate,
//   int32 numSamples, then numSamples x numPoints x float32[3].
//
// Times: PC2 stores frame numbers, not seconds. Sample i sits on scene frame startFrame + i * sampleRate
// (sampleRate is the number of scene frames between samples, as Blender and 3ds Max write it), and pleat
// converts scene frames to seconds with a scene rate (default kDefaultSceneFps = 24, Blender's default):
//   time(i) = (startFrame + i * sampleRate) / scene_fps.
// So a cache with sampleRate 1 plays at scene_fps frames per second. Sample i's source frame number is
// startFrame + i * sampleRate rounded to the nearest integer.
//
// The reader validates the header and the file size when opened (O(1)), and reads one sample at a time
// on demand (O(numPoints) per frame), so long caches stream.
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "sim_io/mesh_sequence.hpp"

namespace pleat {

struct Pc2Header {
  std::int32_t num_points = 0;
  float start_frame = 0.0f;
  float sample_rate = 1.0f;
  std::int32_t num_samples = 0;
};

/// Reads and validates the 32-byte header and that the file holds exactly the samples it announces.
/// Throws InputError naming the file and the byte offset (wrong magic, bad version, negative counts,
/// non-positive or non-finite sampleRate, truncated or oversized file).
Pc2Header read_pc2_header(const std::filesystem::path& path);

/// A FrameSource over a PC2 file. read_frame(i) throws InputError naming the file, the frame and the
/// vertex of a NaN/Inf coordinate, or the byte offset if the file shrank since it was opened.
std::unique_ptr<FrameSource> open_pc2(const std::filesystem::path& path, double scene_fps = kDefaultSceneFps);

/// Writes frames (each the same number of points) as float32 samples, atomically. Throws
/// std::invalid_argument when frames is empty or the frames differ in size, std::runtime_error on I/O
/// failure.
void write_pc2(const std::filesystem::path& path, const std::vector<std::vector<glm::dvec3>>& frames,
               double start_frame, double sample_rate);

}  // namespace pleat
