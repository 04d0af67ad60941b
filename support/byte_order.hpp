// Little- and big-endian encoding of 32-bit ints and floats for the binary cache formats (PC2 is
// little-endian, MDD big-endian; the cone cache little-endian with 64-bit fields too), independent of the
// host's byte order.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace pleat {

enum class ByteOrder { Little, Big };

}  // namespace pleat

namespace pleat::bytes {

inline std::uint16_t load_u16_le(const unsigned char* p) { return std::uint16_t(p[0] | (p[1] << 8)); }
inline std::uint32_t load_u32_le(const unsigned char* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) |
         (std::uint32_t(p[3]) << 24);
}
inline std::uint32_t load_u32_be(const unsigned char* p) {
  return std::uint32_t(p[3]) | (std::uint32_t(p[2]) << 8) | (std::uint32_t(p[1]) << 16) |
         (std::uint32_t(p[0]) << 24);
}
inline std::int32_t load_i32_le(const unsigned char* p) {
  return std::bit_cast<std::int32_t>(load_u32_le(p));
}
inline std::int32_t load_i32_be(const unsigned char* p) {
  return std::bit_cast<std::int32_t>(load_u32_be(p));
}
inline float load_f32_le(const unsigned char* p) { return std::bit_cast<float>(load_u32_le(p)); }
inline float load_f32_be(const unsigned char* p) { return std::bit_cast<float>(load_u32_be(p)); }

inline void append_u16_le(std::string& out, std::uint16_t v) {
  out.push_back(char(v & 0xFF));
  out.push_back(char(v >> 8));
}
inline void append_u32_le(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xFF));
}
inline void append_u32_be(std::string& out, std::uint32_t v) {
  for (int k = 3; k >= 0; --k) out.push_back(char((v >> (8 * k)) & 0xFF));
}
inline void append_i32_le(std::string& out, std::int32_t v) {
  append_u32_le(out, std::bit_cast<std::uint32_t>(v));
}
inline void append_i32_be(std::string& out, std::int32_t v) {
  append_u32_be(out, std::bit_cast<std::uint32_t>(v));
}
inline void append_f32_le(std::string& out, float v) { append_u32_le(out, std::bit_cast<std::uint32_t>(v)); }
inline void append_f32_be(std::string& out, float v) { append_u32_be(out, std::bit_cast<std::uint32_t>(v)); }
inline std::uint64_t load_u64_le(const unsigned char* p) {
  return std::uint64_t(load_u32_le(p)) | (std::uint64_t(load_u32_le(p + 4)) << 32);
}
inline double load_f64_le(const unsigned char* p) { return std::bit_cast<double>(load_u64_le(p)); }
inline void append_u64_le(std::string& out, std::uint64_t v) {
  append_u32_le(out, std::uint32_t(v & 0xFFFFFFFFu));
  append_u32_le(out, std::uint32_t(v >> 32));
}
inline void append_f64_le(std::string& out, double v) { append_u64_le(out, std::bit_cast<std::uint64_t>(v)); }
inline float load_f32(const unsigned char* p, ByteOrder order) {
  return order == ByteOrder::Little ? load_f32_le(p) : load_f32_be(p);
}

/// Appends one frame of a binary point cache: float32 (x, y, z) per point, in `order`.
inline void append_points(std::string& out, const std::vector<glm::dvec3>& points, ByteOrder order) {
  for (const glm::dvec3& p : points)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t bits = std::bit_cast<std::uint32_t>(float(p[k]));
      order == ByteOrder::Little ? append_u32_le(out, bits) : append_u32_be(out, bits);
    }
}

}  // namespace pleat::bytes
