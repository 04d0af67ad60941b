// Reading input files, with the InputError every reader gives for a missing, unreadable or truncated file:
// the whole file (text formats), its size, or a byte range (binary caches read frame by frame).
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "support/byte_order.hpp"

namespace pleat {

/// The bytes of `path`. Throws InputError(path, "", ...) when it is missing, a directory, or unreadable.
std::string read_whole_file(const std::filesystem::path& path);

/// The size of the regular file `path`. Throws InputError(path, "", ...) when missing or not a file.
std::uint64_t file_size_or_throw(const std::filesystem::path& path);

/// `count` bytes from `offset`. Throws InputError(path, "byte N") naming where the data ends when the file
/// is shorter, InputError(path, "") when it cannot be opened.
std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t offset, std::uint64_t count);

/// Reads one frame of a binary point cache: `points` float32 (x, y, z) triples at `offset`, in `order`.
/// Throws InputError naming the frame, the vertex and the byte of the first non-finite coordinate.
std::vector<glm::dvec3> read_point_block(const std::filesystem::path& path, std::uint64_t offset,
                                         std::uint64_t points, std::size_t frame, ByteOrder order);

}  // namespace pleat
