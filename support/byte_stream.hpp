// ByteWriter / ByteReader: fixed-size values, arrays of them and byte strings appended to / read from a
// byte string in the host's byte order and layout, for bytes that stay on one kind of machine: the messages
// between the ranks of a job and the frames of a checkpoint (cli/). The file formats meant to travel (point
// caches, the cone cache) spell their byte order out with byte_order.hpp instead. Values must be trivially
// copyable. A read past the end throws std::runtime_error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace pleat {

class ByteWriter {
 public:
  template <class T>
  ByteWriter& put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    m_bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
    return *this;
  }
  /// The count (64 bits), then the values.
  template <class T>
  ByteWriter& put_array(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(values.size());
    if (!values.empty())
      m_bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    return *this;
  }
  /// The length (64 bits), then the bytes.
  ByteWriter& put_string(std::string_view text) {
    put<std::uint64_t>(text.size());
    m_bytes.append(text);
    return *this;
  }
  std::string take() { return std::move(m_bytes); }

 private:
  std::string m_bytes;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : m_bytes(bytes) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    need(sizeof value);
    std::memcpy(&value, m_bytes.data() + m_at, sizeof value);
    m_at += sizeof value;
    return value;
  }
  template <class T>
  std::vector<T> get_array() {
    const auto n = get<std::uint64_t>();
    if (n > (m_bytes.size() - m_at) / sizeof(T)) throw std::runtime_error("byte string truncated");
    std::vector<T> values(n);
    if (n != 0)
      std::memcpy(values.data(), m_bytes.data() + m_at,
                  n * sizeof(T));  // an empty vector's data() may be null
    m_at += n * sizeof(T);
    return values;
  }
  std::string_view get_string() {
    const auto n = get<std::uint64_t>();
    need(n);
    const std::string_view s = m_bytes.substr(m_at, n);
    m_at += n;
    return s;
  }
  /// What is left unread.
  std::string_view rest() const { return m_bytes.substr(m_at); }

 private:
  void need(std::size_t n) const {
    if (m_bytes.size() - m_at < n) throw std::runtime_error("byte string truncated");
  }
  std::string_view m_bytes;
  std::size_t m_at = 0;
};

}  // namespace pleat
