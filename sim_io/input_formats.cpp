// The tables of input_formats.hpp: one row per format, the format in its reader's file.
#include "sim_io/input_formats.hpp"

#include <cctype>

#include "support/input_error.hpp"

namespace pleat {
namespace formats {

extern const MeshFormat kObj, kGltf, kGlb, kObjSequence;
extern const CacheFormat kPc2, kMdd;

const MeshFormat* const kMesh[] = {
    &kObj,
    &kGltf,
    &kGlb,
    &kObjSequence,
};

const CacheFormat* const kCache[] = {
    &kPc2,
    &kMdd,
};

}  // namespace formats

namespace {

std::string lower_extension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

const MeshFormat* find_mesh_format(const std::filesystem::path& input) {
  for (const MeshFormat* format : mesh_formats())
    if (format->claims && format->claims(input)) return format;
  const std::string extension = lower_extension(input);
  for (const MeshFormat* format : mesh_formats())
    if (!format->extension.empty() && format->extension == extension) return format;
  return nullptr;
}

}  // namespace

std::span<const MeshFormat* const> mesh_formats() { return formats::kMesh; }
std::span<const CacheFormat* const> cache_formats() { return formats::kCache; }

const MeshFormat& mesh_format_of(const std::filesystem::path& input) {
  if (const MeshFormat* format = find_mesh_format(input)) return *format;
  std::string expected;
  for (const MeshFormat* format : mesh_formats())
    expected += (expected.empty() ? "" : ", ") + std::string(format->expected);
  throw InputError(input.string(), "", "unknown input format (expected " + expected + ")");
}

const CacheFormat& cache_format_of(const std::filesystem::path& cache) {
  const std::string extension = lower_extension(cache);
  std::string expected;
  for (std::size_t i = 0; i < cache_formats().size(); ++i) {
    const CacheFormat* format = cache_formats()[i];
    if (format->extension == extension) return *format;
    expected += (i == 0                            ? ""
                 : i + 1 == cache_formats().size() ? " or "
                                                   : ", ") +
                std::string(format->extension);
  }
  throw InputError(cache.string(), "", "unknown cache format (expected " + expected + ")");
}

std::vector<std::filesystem::path> files_read_by(const std::filesystem::path& input) {
  const MeshFormat* format = find_mesh_format(input);
  if (!format || !format->files_read) return {input};
  return format->files_read(input);
}

std::unique_ptr<FrameSource> open_cache_for(const std::filesystem::path& cache, Index num_vertices,
                                            const std::string& mesh, double scene_fps) {
  std::unique_ptr<FrameSource> source = cache_format_of(cache).open(cache, scene_fps);
  const FrameSource::Announced announced = source->announced_points();
  if (announced.points >= 0 && announced.points != std::int64_t(num_vertices))
    throw InputError(cache.string(), announced.place,
                     "vertex-count mismatch: the cache has " + std::to_string(announced.points) +
                         " points, " + mesh + " has " + std::to_string(num_vertices) + " vertices");
  return source;
}

}  // namespace pleat
