#include "sim_io/input_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "support/byte_order.hpp"
#include "support/input_error.hpp"

namespace pleat {

std::string read_whole_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw InputError(path.string(), "", "no such file");
  if (std::filesystem::is_directory(status))
    throw InputError(path.string(), "", "is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", std::string("cannot open: ") + std::strerror(errno));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string(), "", "read error");
  return bytes;
}

std::uint64_t file_size_or_throw(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw InputError(path.string(), "", "no such file");
  if (!std::filesystem::is_regular_file(status)) throw InputError(path.string(), "", "not a regular file");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path.string(), "", "cannot read its size: " + ec.message());
  return size;
}

std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t offset, std::uint64_t count) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", std::string("cannot open: ") + std::strerror(errno));
  std::string bytes(count, '\0');
  in.seekg(std::streamoff(offset));
  in.read(bytes.data(), std::streamsize(count));
  const auto got = std::uint64_t(in.gcount());
  if (got != count)
    throw InputError(
        path.string(), "byte " + std::to_string(offset + got),
        "truncated: expected " + std::to_string(count) + " bytes from byte " + std::to_string(offset));
  return bytes;
}

std::vector<glm::dvec3> read_point_block(const std::filesystem::path& path, std::uint64_t offset,
                                         std::uint64_t points, std::size_t frame, ByteOrder order) {
  const std::string bytes = read_file_bytes(path, offset, points * 12);
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::vector<glm::dvec3> positions(points);
  for (std::uint64_t v = 0; v < points; ++v)
    for (int k = 0; k < 3; ++k) {
      const unsigned char* at = p + 12 * v + 4 * k;
      const float c = bytes::load_f32(at, order);
      if (!std::isfinite(c))
        throw InputError(path.string(), "frame " + std::to_string(frame) + ", vertex " + std::to_string(v),
                         "non-finite coordinate (byte " + std::to_string(offset + 12 * v + 4 * k) + ")");
      positions[v][k] = double(c);
    }
  return positions;
}

}  // namespace pleat
