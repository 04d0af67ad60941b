#include "sim_io/load_sequence.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sim_io/input_formats.hpp"
#include "support/input_error.hpp"

namespace pleat {

MeshSequence load_sequence(const std::filesystem::path& input, const std::filesystem::path& cache) {
  return load_sequence(input, cache, LoadOptions{});
}

MeshSequence load_sequence(const std::filesystem::path& input, const std::filesystem::path& cache,
                           const LoadOptions& options) {
  if (!(options.scene_fps > 0.0) || !std::isfinite(options.scene_fps))
    throw std::invalid_argument("load_sequence: scene_fps must be positive");
  const MeshFormat& format = mesh_format_of(input);
  if (!cache.empty() && !format.cache_refusal.empty())
    throw InputError(cache.string(), "",
                     "a cache goes with a single .obj, not with " + std::string(format.cache_refusal));
  return format.open(input, cache, options);
}

}  // namespace pleat
