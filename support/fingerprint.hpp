// FNV-1a 64 (Fowler–Noll–Vo): the project's one fingerprint hash, for the identity of a mesh, a frame, a job
// (the cone cache's header, the checkpoints of cli/chunk_plan.hpp). Not for security.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace pleat {

class Fingerprint {
 public:
  /// The bytes [data, data + size), in order.
  Fingerprint& add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) add_byte(bytes[i]);
    return *this;
  }
  Fingerprint& add(std::string_view text) { return add(text.data(), text.size()); }
  /// The object representation of `value` (host byte order: for fingerprints that stay on one machine).
  template <class T>
  Fingerprint& add_value(const T& value) {
    return add(&value, sizeof value);
  }
  /// The `bytes` low-order bytes of `value`, least significant first (the same on every host: for
  /// fingerprints stored in files).
  Fingerprint& add_le(std::uint64_t value, int bytes) {
    for (int k = 0; k < bytes; ++k) add_byte(static_cast<unsigned char>((value >> (8 * k)) & 0xFFu));
    return *this;
  }
  std::uint64_t value() const { return m_hash; }

 private:
  void add_byte(unsigned char byte) { m_hash = (m_hash ^ byte) * 0x100000001b3ull; }
  std::uint64_t m_hash = 0xcbf29ce484222325ull;
};

}  // namespace pleat
