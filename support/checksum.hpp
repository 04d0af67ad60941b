// CRC-32 (the ISO-HDLC polynomial of zlib, gzip and PNG, computed by zlib): the checksum stored in pleat's
// own files (the cone cache, checkpoint chunks), so that a damaged file (a flipped bit, a lost or zeroed
// block) is told from a good one before it is used. It catches every burst of up to 32 changed bits and
// every odd number of flipped bits, and misses other damage with probability 2^-32. Not for security. Cost:
// about a byte per cycle.
#pragma once

#include <zlib.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace pleat {

class Checksum {
 public:
  /// The bytes [data, data + size), in order.
  Checksum& add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const Bytef*>(data);
    while (size > 0) {  // zlib takes at most a uInt at a time
      const auto n = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
      m_crc = ::crc32(m_crc, bytes, n);
      bytes += n;
      size -= n;
    }
    return *this;
  }
  Checksum& add(std::string_view bytes) { return add(bytes.data(), bytes.size()); }
  std::uint32_t value() const { return static_cast<std::uint32_t>(m_crc); }

 private:
  uLong m_crc = ::crc32(0L, Z_NULL, 0);
};

/// The CRC-32 of `bytes`.
inline std::uint32_t checksum(std::string_view bytes) { return Checksum().add(bytes).value(); }

}  // namespace pleat
