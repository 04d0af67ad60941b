#include "sim_io/pc2_format.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

#include "sim_io/input_file.hpp"
#include "sim_io/input_formats.hpp"
#include "support/atomic_file.hpp"
#include "support/byte_order.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

constexpr char kMagic[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
constexpr std::uint64_t kHeaderBytes = 32;

std::string at_byte(std::uint64_t offset) { return "byte " + std::to_string(offset); }

class Pc2Source : public FrameSource {
 public:
  Pc2Source(std::filesystem::path path, Pc2Header header, double scene_fps)
      : m_path(std::move(path)), m_header(header), m_scene_fps(scene_fps) {}

  std::size_t num_frames() const override { return std::size_t(m_header.num_samples); }
  std::int64_t source_frame(std::size_t i) const override {
    return std::llround(double(m_header.start_frame) + double(i) * double(m_header.sample_rate));
  }
  double frame_time(std::size_t i) const override {
    return (double(m_header.start_frame) + double(i) * double(m_header.sample_rate)) / m_scene_fps;
  }
  std::vector<glm::dvec3> read_frame(std::size_t i) const override {
    const auto points = std::uint64_t(m_header.num_points);
    const std::uint64_t offset = kHeaderBytes + std::uint64_t(i) * points * 12;
    return read_point_block(m_path, offset, points, i, ByteOrder::Little);
  }
  Announced announced_points() const override { return {m_header.num_points, "byte 16"}; }

 private:
  std::filesystem::path m_path;
  Pc2Header m_header;
  double m_scene_fps;
};

}  // namespace

Pc2Header read_pc2_header(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::uint64_t size = file_size_or_throw(path);
  if (size < kHeaderBytes)
    throw InputError(file, at_byte(size),
                     "truncated: the PC2 header needs 32 bytes, the file has " + std::to_string(size));
  const std::string head = read_file_bytes(path, 0, kHeaderBytes);
  const auto* p = reinterpret_cast<const unsigned char*>(head.data());
  if (std::memcmp(head.data(), kMagic, sizeof kMagic) != 0)
    throw InputError(file, at_byte(0), "wrong magic: not a PC2 file (expected \"POINTCACHE2\")");
  const std::int32_t version = bytes::load_i32_le(p + 12);
  if (version != 1) throw InputError(file, at_byte(12), "unsupported PC2 version " + std::to_string(version));
  Pc2Header header;
  header.num_points = bytes::load_i32_le(p + 16);
  header.start_frame = bytes::load_f32_le(p + 20);
  header.sample_rate = bytes::load_f32_le(p + 24);
  header.num_samples = bytes::load_i32_le(p + 28);
  if (header.num_points <= 0)
    throw InputError(file, at_byte(16),
                     "numPoints is " + std::to_string(header.num_points) + ", must be positive");
  if (!std::isfinite(header.start_frame)) throw InputError(file, at_byte(20), "startFrame is not finite");
  if (!std::isfinite(header.sample_rate) || header.sample_rate <= 0.0f)
    throw InputError(file, at_byte(24), "sampleRate must be positive and finite");
  if (header.num_samples <= 0)
    throw InputError(file, at_byte(28),
                     "numSamples is " + std::to_string(header.num_samples) + ", must be positive");
  const std::uint64_t expected =
      kHeaderBytes + std::uint64_t(header.num_samples) * std::uint64_t(header.num_points) * 12;
  if (size < expected)
    throw InputError(file, at_byte(size),
                     "truncated: " + std::to_string(header.num_samples) + " samples of " +
                         std::to_string(header.num_points) + " points need " + std::to_string(expected) +
                         " bytes, the file has " + std::to_string(size));
  if (size > expected)
    throw InputError(file, at_byte(expected),
                     std::to_string(size - expected) +
                         " unexpected bytes after the last sample (header says " +
                         std::to_string(header.num_samples) + " samples of " +
                         std::to_string(header.num_points) + " points)");
  return header;
}

std::unique_ptr<FrameSource> open_pc2(const std::filesystem::path& path, double scene_fps) {
  if (!(scene_fps > 0.0) || !std::isfinite(scene_fps))
    throw std::invalid_argument("open_pc2: scene_fps must be positive");
  return std::make_unique<Pc2Source>(path, read_pc2_header(path), scene_fps);
}

void write_pc2(const std::filesystem::path& path, const std::vector<std::vector<glm::dvec3>>& frames,
               double start_frame, double sample_rate) {
  if (frames.empty()) throw std::invalid_argument("write_pc2: no frames");
  const std::size_t points = frames.front().size();
  if (points == 0) throw std::invalid_argument("write_pc2: no points");
  for (const auto& f : frames)
    if (f.size() != points) throw std::invalid_argument("write_pc2: frames differ in their number of points");
  if (points > std::size_t(INT32_MAX) || frames.size() > std::size_t(INT32_MAX))
    throw std::invalid_argument("write_pc2: too many points or frames for PC2's int32 counts");
  write_file_atomically(path, [&](std::ostream& out) {
    std::string header(kMagic, sizeof kMagic);
    bytes::append_i32_le(header, 1);
    bytes::append_i32_le(header, std::int32_t(points));
    bytes::append_f32_le(header, float(start_frame));
    bytes::append_f32_le(header, float(sample_rate));
    bytes::append_i32_le(header, std::int32_t(frames.size()));
    out.write(header.data(), std::streamsize(header.size()));
    std::string sample;
    sample.reserve(points * 12);
    for (const auto& f : frames) {
      sample.clear();
      bytes::append_points(sample, f, ByteOrder::Little);
      out.write(sample.data(), std::streamsize(sample.size()));
    }
  });
}

namespace formats {
extern const CacheFormat kPc2{
    ".pc2", [](const std::filesystem::path& path, double scene_fps) { return open_pc2(path, scene_fps); }};
}  // namespace formats

}  // namespace pleat
