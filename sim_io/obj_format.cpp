#include "sim_io/obj_format.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sim_io/atomic_file.hpp"
#include "sim_io/input_file.hpp"
#include "static_core/input_error.hpp"

namespace pleat {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Splits a line into whitespace-separated tokens (views into the line).
class Tokens {
 public:
  explicit Tokens(std::string_view line) : m_rest(line) {}
  bool next(std::string_view& token) {
    std::size_t i = 0;
    while (i < m_rest.size() && is_space(m_rest[i])) ++i;
    if (i == m_rest.size()) return false;
    std::size_t j = i;
    while (j < m_rest.size() && !is_space(m_rest[j])) ++j;
    token = m_rest.substr(i, j - i);
    m_rest = m_rest.substr(j);
    return true;
  }

 private:
  std::string_view m_rest;
};

bool parse_double(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

bool parse_index(std::string_view token, std::int64_t& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

std::string at_line(std::size_t line) { return "line " + std::to_string(line); }

// Appends the shortest decimal form of v that reads back to the same double.
void append_double(std::string& out, double v) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, end);
}

}  // namespace

ObjMesh read_obj(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string text = read_whole_file(path);
  ObjMesh mesh;
  // Positive indices may refer to vertices defined later in the file; check them once all are known.
  std::int64_t max_positive_index = 0;
  std::size_t max_positive_line = 0;
  std::vector<std::int64_t> corners;

  std::size_t line_number = 0;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + begin, end - begin);
    begin = end + 1;
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    Tokens tokens(line);
    std::string_view keyword;
    if (!tokens.next(keyword)) continue;

    if (keyword == "v") {
      glm::dvec3 p;
      for (int k = 0; k < 3; ++k) {
        std::string_view token;
        if (!tokens.next(token))
          throw InputError(file, at_line(line_number), "vertex has fewer than 3 coordinates");
        if (!parse_double(token, p[k]))
          throw InputError(file, at_line(line_number),
                           "vertex coordinate '" + std::string(token) + "' is not a number");
        if (!std::isfinite(p[k]))
          throw InputError(
              file, at_line(line_number),
              "vertex " + std::to_string(mesh.positions.size()) + " has a non-finite coordinate");
      }
      mesh.positions.push_back(p);  // extra values (w, or r g b vertex colours) are ignored
    } else if (keyword == "f") {
      corners.clear();
      std::string_view token;
      while (tokens.next(token)) {
        const std::string_view index_text = token.substr(0, token.find('/'));
        std::int64_t index = 0;
        if (!parse_index(index_text, index))
          throw InputError(file, at_line(line_number),
                           "face corner '" + std::string(token) + "' is not an index");
        const auto count = std::int64_t(mesh.positions.size());
        if (index == 0)
          throw InputError(file, at_line(line_number), "vertex index 0 (OBJ indices start at 1)");
        if (index < 0) {
          if (-index > count)
            throw InputError(file, at_line(line_number),
                             "relative vertex index " + std::to_string(index) + " out of range (" +
                                 std::to_string(count) + " vertices so far)");
          corners.push_back(count + index);
        } else {
          if (index > max_positive_index) {
            max_positive_index = index;
            max_positive_line = line_number;
          }
          corners.push_back(index - 1);
        }
      }
      if (corners.size() < 3)
        throw InputError(file, at_line(line_number),
                         "face has " + std::to_string(corners.size()) + " corners, needs 3");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        mesh.triangles.push_back({Index(corners[0]), Index(corners[k]), Index(corners[k + 1])});
      ++mesh.num_polygons;
    }
  }
  if (max_positive_index > std::int64_t(mesh.positions.size()))
    throw InputError(file, at_line(max_positive_line),
                     "vertex index " + std::to_string(max_positive_index) + " out of range (" +
                         std::to_string(mesh.positions.size()) + " vertices)");
  if (mesh.positions.size() > std::size_t(UINT32_MAX))
    throw InputError(file, "", "too many vertices for 32-bit indices");
  if (mesh.positions.empty()) throw InputError(file, "", "empty mesh: no vertices");
  if (mesh.triangles.empty()) throw InputError(file, "", "empty mesh: no faces");
  return mesh;
}

void write_obj(const std::filesystem::path& path, const MeshTopology& topology,
               const std::vector<glm::dvec3>& positions) {
  if (positions.size() != topology.num_vertices)
    throw std::invalid_argument("write_obj: " + std::to_string(positions.size()) + " positions for " +
                                std::to_string(topology.num_vertices) + " vertices");
  for (const Triangle& t : topology.triangles)
    for (Index v : t)
      if (v >= topology.num_vertices) throw std::invalid_argument("write_obj: triangle index out of range");
  write_file_atomically(path, [&](std::ostream& out) {
    std::string chunk = "# written by pleat\n";
    const auto flush_if_large = [&] {
      if (chunk.size() > (1u << 20)) {
        out.write(chunk.data(), std::streamsize(chunk.size()));
        chunk.clear();
      }
    };
    for (const glm::dvec3& p : positions) {
      chunk += "v ";
      append_double(chunk, p.x);
      chunk += ' ';
      append_double(chunk, p.y);
      chunk += ' ';
      append_double(chunk, p.z);
      chunk += '\n';
      flush_if_large();
    }
    for (const Triangle& t : topology.triangles) {
      chunk += "f " + std::to_string(t[0] + 1) + ' ' + std::to_string(t[1] + 1) + ' ' +
               std::to_string(t[2] + 1) + '\n';
      flush_if_large();
    }
    out.write(chunk.data(), std::streamsize(chunk.size()));
  });
}

}  // namespace pleat
