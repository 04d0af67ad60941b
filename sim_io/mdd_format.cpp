#include "sim_io/mdd_format.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sim_io/input_file.hpp"
#include "sim_io/input_formats.hpp"
#include "support/atomic_file.hpp"
#include "support/byte_order.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

std::string at_byte(std::uint64_t offset) { return "byte " + std::to_string(offset); }

// When the header read little-endian describes the file exactly, the hint that it was written so (MDD is
// big-endian): appended to what is wrong with it read big-endian.
std::string little_endian_hint(const unsigned char* header, std::uint64_t size) {
  const std::int64_t frames = bytes::load_i32_le(header), points = bytes::load_i32_le(header + 4);
  if (frames <= 0 || points <= 0 || 8 + 4 * std::uint64_t(frames) * (1 + 3 * std::uint64_t(points)) != size)
    return "";
  return "; read little-endian, the header says " + std::to_string(frames) + " frames of " +
         std::to_string(points) +
         " points, which fits the file exactly: MDD is big-endian, and this file was written little-endian "
         "(export it again as MDD, or as PC2)";
}

class MddSource : public FrameSource {
 public:
  MddSource(std::filesystem::path path, MddHeader header, double scene_fps)
      : m_path(std::move(path)), m_header(std::move(header)), m_scene_fps(scene_fps) {}

  std::size_t num_frames() const override { return std::size_t(m_header.num_frames); }
  double frame_time(std::size_t i) const override { return m_header.times.at(i); }
  std::int64_t source_frame(std::size_t i) const override {
    return std::llround(m_header.times.at(i) * m_scene_fps);
  }
  std::vector<glm::dvec3> read_frame(std::size_t i) const override {
    const auto points = std::uint64_t(m_header.num_points);
    const std::uint64_t offset = 8 + 4 * std::uint64_t(m_header.num_frames) + std::uint64_t(i) * points * 12;
    return read_point_block(m_path, offset, points, i, ByteOrder::Big);
  }
  Announced announced_points() const override { return {m_header.num_points, "byte 4"}; }

 private:
  std::filesystem::path m_path;
  MddHeader m_header;
  double m_scene_fps;
};

}  // namespace

MddHeader read_mdd_header(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::uint64_t size = file_size_or_throw(path);
  if (size < 8)
    throw InputError(file, at_byte(size),
                     "truncated: the MDD header needs 8 bytes, the file has " + std::to_string(size));
  const std::string head = read_file_bytes(path, 0, 8);
  const auto* p = reinterpret_cast<const unsigned char*>(head.data());
  MddHeader header;
  header.num_frames = bytes::load_i32_be(p);
  header.num_points = bytes::load_i32_be(p + 4);
  if (header.num_frames <= 0)
    throw InputError(file, at_byte(0),
                     "frameCount is " + std::to_string(header.num_frames) +
                         ", must be positive (is this an MDD file?)" + little_endian_hint(p, size));
  if (header.num_points <= 0)
    throw InputError(file, at_byte(4),
                     "vertCount is " + std::to_string(header.num_points) + ", must be positive" +
                         little_endian_hint(p, size));
  const auto frames = std::uint64_t(header.num_frames);
  const std::uint64_t expected = 8 + 4 * frames + frames * std::uint64_t(header.num_points) * 12;
  if (size < expected)
    throw InputError(file, at_byte(size),
                     "truncated: " + std::to_string(frames) + " frames of " +
                         std::to_string(header.num_points) + " points need " + std::to_string(expected) +
                         " bytes, the file has " + std::to_string(size) + little_endian_hint(p, size));
  if (size > expected)
    throw InputError(file, at_byte(expected),
                     std::to_string(size - expected) +
                         " unexpected bytes after the last frame (header says " + std::to_string(frames) +
                         " frames of " + std::to_string(header.num_points) + " points)" +
                         little_endian_hint(p, size));
  const std::string time_bytes = read_file_bytes(path, 8, 4 * frames);
  const auto* t = reinterpret_cast<const unsigned char*>(time_bytes.data());
  header.times.resize(frames);
  for (std::uint64_t i = 0; i < frames; ++i) {
    const float time = bytes::load_f32_be(t + 4 * i);
    if (!std::isfinite(time))
      throw InputError(file, at_byte(8 + 4 * i), "time of frame " + std::to_string(i) + " is not finite");
    if (i > 0 && !(double(time) > header.times[i - 1]))
      throw InputError(file, at_byte(8 + 4 * i), "time of frame " + std::to_string(i) + " does not increase");
    header.times[i] = double(time);
  }
  return header;
}

std::unique_ptr<FrameSource> open_mdd(const std::filesystem::path& path, double scene_fps) {
  if (!(scene_fps > 0.0) || !std::isfinite(scene_fps))
    throw std::invalid_argument("open_mdd: scene_fps must be positive");
  return std::make_unique<MddSource>(path, read_mdd_header(path), scene_fps);
}

void write_mdd(const std::filesystem::path& path, const std::vector<std::vector<glm::dvec3>>& frames,
               const std::vector<double>& times) {
  if (frames.empty()) throw std::invalid_argument("write_mdd: no frames");
  if (times.size() != frames.size()) throw std::invalid_argument("write_mdd: one time per frame");
  const std::size_t points = frames.front().size();
  if (points == 0) throw std::invalid_argument("write_mdd: no points");
  for (const auto& f : frames)
    if (f.size() != points) throw std::invalid_argument("write_mdd: frames differ in their number of points");
  if (points > std::size_t(INT32_MAX) || frames.size() > std::size_t(INT32_MAX))
    throw std::invalid_argument("write_mdd: too many points or frames for MDD's int32 counts");
  write_file_atomically(path, [&](std::ostream& out) {
    std::string header;
    bytes::append_i32_be(header, std::int32_t(frames.size()));
    bytes::append_i32_be(header, std::int32_t(points));
    for (double t : times) bytes::append_f32_be(header, float(t));
    out.write(header.data(), std::streamsize(header.size()));
    std::string frame;
    frame.reserve(points * 12);
    for (const auto& f : frames) {
      frame.clear();
      bytes::append_points(frame, f, ByteOrder::Big);
      out.write(frame.data(), std::streamsize(frame.size()));
    }
  });
}

namespace formats {
extern const CacheFormat kMdd{
    ".mdd", [](const std::filesystem::path& path, double scene_fps) { return open_mdd(path, scene_fps); }};
}  // namespace formats

}  // namespace pleat
