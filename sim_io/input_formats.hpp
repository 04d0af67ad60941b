// The input formats pleat reads, one table each for meshes and point caches: {extension -> open}, as libigl's
// read_triangle_mesh dispatches. A mesh format opens INPUT (and its --cache, for formats that take one) into
// a MeshSequence; a cache format opens a point cache into a FrameSource that announces its point count. Each
// format is a unit of its own (its reader's file, where its row is defined) and one row of its table
// (input_formats.cpp); load_sequence, the "unknown format" messages and the files an input reads
// (files_read_by: what the command line protects from being overwritten) all go through the tables.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"

namespace pleat {

struct MeshFormat {
  /// Lower case, with its dot (".obj"); empty for a format claimed by `claims` (an OBJ sequence).
  std::string_view extension;
  /// How "unknown input format (expected ...)" lists it.
  std::string_view expected;
  /// Empty: it takes a --cache; otherwise what a cache given with it is refused for ("not with glTF").
  std::string_view cache_refusal;
  /// Null: claimed by its extension alone; otherwise whether `input` is this format's (checked before any
  /// extension).
  bool (*claims)(const std::filesystem::path& input);
  /// The sequence; throws InputError on anything malformed.
  MeshSequence (*open)(const std::filesystem::path& input, const std::filesystem::path& cache,
                       const LoadOptions& options);
  /// Null: the input alone; otherwise every file reading `input` reads (never throws: a malformed input
  /// gives what it names).
  std::vector<std::filesystem::path> (*files_read)(const std::filesystem::path& input);
};

struct CacheFormat {
  std::string_view extension;  ///< lower case, with its dot (".pc2")
  /// The frames of the cache at `path` (its header validated: InputError naming the file and the byte).
  std::unique_ptr<FrameSource> (*open)(const std::filesystem::path& path, double scene_fps);
};

std::span<const MeshFormat* const> mesh_formats();
std::span<const CacheFormat* const> cache_formats();

/// The format of INPUT: the first row that claims it, else the row of its extension (any case). Throws
/// InputError naming the input and listing the formats when none.
const MeshFormat& mesh_format_of(const std::filesystem::path& input);
/// The format of a cache by its extension; InputError naming the cache and listing the formats when none.
const CacheFormat& cache_format_of(const std::filesystem::path& cache);

/// The files reading `input` reads (its format's files_read; the input itself for an unknown format).
std::vector<std::filesystem::path> files_read_by(const std::filesystem::path& input);

/// A cache's frames for a mesh of `num_vertices` vertices: opened by its format, the count its header
/// announces checked against the mesh's (InputError naming the cache and the place, and `mesh`).
std::unique_ptr<FrameSource> open_cache_for(const std::filesystem::path& cache, Index num_vertices,
                                            const std::string& mesh, double scene_fps);

}  // namespace pleat
