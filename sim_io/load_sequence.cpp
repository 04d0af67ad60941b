#include "sim_io/load_sequence.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sim_io/gltf_reader.hpp"
#include "sim_io/mdd_format.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/obj_sequence.hpp"
#include "sim_io/pc2_format.hpp"
#include "static_core/input_error.hpp"

namespace pleat {

namespace {

std::string lower_extension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

}  // namespace

MeshSequence load_sequence(const std::filesystem::path& input, const std::filesystem::path& cache) {
  return load_sequence(input, cache, LoadOptions{});
}

MeshSequence load_sequence(const std::filesystem::path& input, const std::filesystem::path& cache,
                           const LoadOptions& options) {
  if (!(options.scene_fps > 0.0) || !std::isfinite(options.scene_fps))
    throw std::invalid_argument("load_sequence: scene_fps must be positive");
  const std::string name = input.string();
  std::error_code ec;
  const bool is_directory = std::filesystem::is_directory(input, ec);
  const std::string extension = lower_extension(input);

  if (is_directory || is_frame_pattern(name)) {
    if (!cache.empty())
      throw InputError(cache.string(), "", "a cache goes with a single .obj, not with an OBJ sequence");
    const auto files = is_directory ? list_obj_directory(input) : expand_frame_pattern(name);
    return load_obj_sequence(name, files, options.scene_fps, options.scan);
  }
  if (extension == ".gltf" || extension == ".glb") {
    if (!cache.empty())
      throw InputError(cache.string(), "", "a cache goes with a single .obj, not with glTF");
    return load_gltf(input, options.scene_fps, options.scan);
  }
  if (extension != ".obj")
    throw InputError(
        name, "",
        "unknown input format (expected .obj [+ .pc2/.mdd cache], .gltf, .glb, a directory of .obj "
        "files or a printf pattern like frames/f_%04d.obj)");

  ObjMesh mesh = read_obj(input);
  const auto num_vertices = Index(mesh.positions.size());
  SurfaceAttributes surface = surface_of(mesh);
  if (cache.empty()) {
    std::vector<std::vector<glm::dvec3>> frames;
    frames.push_back(std::move(mesh.positions));
    return MeshSequence(name, std::move(mesh.triangles), num_vertices,
                        make_memory_source(std::move(frames), {0.0}), options.scan, std::move(surface));
  }
  const std::string cache_extension = lower_extension(cache);
  std::unique_ptr<FrameSource> source;
  std::int64_t cache_points = 0;
  std::string count_place;
  if (cache_extension == ".pc2") {
    cache_points = read_pc2_header(cache).num_points;
    count_place = "byte 16";
    source = open_pc2(cache, options.scene_fps);
  } else if (cache_extension == ".mdd") {
    cache_points = read_mdd_header(cache).num_points;
    count_place = "byte 4";
    source = open_mdd(cache, options.scene_fps);
  } else {
    throw InputError(cache.string(), "", "unknown cache format (expected .pc2 or .mdd)");
  }
  if (cache_points != std::int64_t(num_vertices))
    throw InputError(cache.string(), count_place,
                     "vertex-count mismatch: the cache has " + std::to_string(cache_points) + " points, " +
                         name + " has " + std::to_string(num_vertices) + " vertices");
  // Name the sequence after the cache: frame-level errors (NaN, truncation) are about its bytes.
  return MeshSequence(cache.string(), std::move(mesh.triangles), num_vertices, std::move(source),
                      options.scan, std::move(surface));
}

}  // namespace pleat
