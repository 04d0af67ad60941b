#include "sim_io/obj_format.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sim_io/input_file.hpp"
#include "sim_io/input_formats.hpp"
#include "sim_io/polygon_triangulation.hpp"
#include "support/atomic_file.hpp"
#include "support/input_error.hpp"

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

namespace {

// An index into one of the OBJ's lists (v, vt or vn) as a face corner gives it: 1-based, or negative counting
// back from the last element defined so far. Positive indices may refer to elements defined later in the
// file; `max_positive` remembers the largest one (and its line) to check once all are known.
struct IndexList {
  const char* what;    // "vertex", "texture coordinate", "normal"
  const char* plural;  // "vertices", ...
  std::int64_t max_positive = 0;
  std::size_t max_positive_line = 0;

  std::int64_t resolve(std::string_view text, std::int64_t count, const std::string& file, std::size_t line,
                       std::string_view token) {
    std::int64_t index = 0;
    if (!parse_index(text, index))
      throw InputError(file, at_line(line), "face corner '" + std::string(token) + "' is not an index");
    if (index == 0)
      throw InputError(file, at_line(line), std::string(what) + " index 0 (OBJ indices start at 1)");
    if (index < 0) {
      if (-index > count)
        throw InputError(file, at_line(line),
                         "relative " + std::string(what) + " index " + std::to_string(index) +
                             " out of range (" + std::to_string(count) + " " + plural + " so far)");
      return count + index;
    }
    if (index > max_positive) {
      max_positive = index;
      max_positive_line = line;
    }
    return index - 1;
  }
  void check(std::size_t count, const std::string& file) const {
    if (max_positive > std::int64_t(count))
      throw InputError(file, at_line(max_positive_line),
                       std::string(what) + " index " + std::to_string(max_positive) + " out of range (" +
                           std::to_string(count) + " " + plural + ")");
  }
};

// Reads `count` numbers after a keyword into `out`; the place names `what`.
template <int N>
void read_numbers(Tokens& tokens, int required, double* out, const char* what, const std::string& file,
                  std::size_t line) {
  for (int k = 0; k < N; ++k) {
    std::string_view token;
    if (!tokens.next(token)) {
      if (k < required)
        throw InputError(file, at_line(line),
                         std::string(what) + " has fewer than " + std::to_string(required) + " coordinates");
      out[k] = 0.0;
      continue;
    }
    if (!parse_double(token, out[k]))
      throw InputError(file, at_line(line),
                       std::string(what) + " coordinate '" + std::string(token) + "' is not a number");
    if (!std::isfinite(out[k]))
      throw InputError(file, at_line(line), std::string(what) + " has a non-finite coordinate");
  }
}

}  // namespace

namespace {

// One corner of an `f` statement: 0-based indices of its vertex, texture coordinate and normal (-1: none).
struct Corner {
  std::int64_t v, t, n;
};

// The OBJ's statements as read: everything of ObjMesh but the triangles, and every polygon's corners.
struct ParsedObj {
  ObjMesh mesh;
  std::vector<Corner> corners;  // polygon p's: corners[mesh.polygon_starts[p] .. mesh.polygon_starts[p + 1])
};

ParsedObj starting_parse() {
  ParsedObj parsed;
  parsed.mesh.polygon_starts.push_back(0);
  return parsed;
}

class ObjParser {
 public:
  explicit ObjParser(std::string file) : m_file(std::move(file)) {}

  void parse(std::string_view text) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte-order mark
    std::size_t line_number = 0;
    std::size_t begin = 0;
    while (begin < text.size()) {
      std::size_t end = text.find('\n', begin);
      if (end == std::string::npos) end = text.size();
      std::string_view line = text.substr(begin, end - begin);
      begin = end + 1;
      ++line_number;
      if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
      statement(line, line_number);
    }
  }

  ParsedObj finish() {
    ObjMesh& mesh = m_parsed.mesh;
    m_vertex_index.check(mesh.positions.size(), m_file);
    m_texcoord_index.check(mesh.texcoords.size(), m_file);
    m_normal_index.check(mesh.normals.size(), m_file);
    if (mesh.positions.size() > std::size_t(UINT32_MAX))
      throw InputError(m_file, "", "too many vertices for 32-bit indices");
    if (mesh.positions.empty()) throw InputError(m_file, "", "empty mesh: no vertices");
    if (mesh.num_polygons == 0) throw InputError(m_file, "", "empty mesh: no faces");
    return std::move(m_parsed);
  }

 private:
  void statement(std::string_view line, std::size_t line_number) {
    Tokens tokens(line);
    std::string_view keyword;
    if (!tokens.next(keyword)) return;
    ObjMesh& mesh = m_parsed.mesh;
    if (keyword == "v") {
      mesh.positions.push_back(vertex(tokens, line_number));  // w or r g b colours are ignored
    } else if (keyword == "vt") {
      double uv[2];
      read_numbers<2>(tokens, 1, uv, "texture coordinate", m_file, line_number);  // a w is ignored
      mesh.texcoords.emplace_back(uv[0], uv[1]);
    } else if (keyword == "vn") {
      double n[3];
      read_numbers<3>(tokens, 3, n, "normal", m_file, line_number);
      mesh.normals.emplace_back(n[0], n[1], n[2]);
    } else if (keyword == "f") {
      face(tokens, line_number);
    }
  }

  glm::dvec3 vertex(Tokens& tokens, std::size_t line_number) const {
    glm::dvec3 p;
    for (int k = 0; k < 3; ++k) {
      std::string_view token;
      if (!tokens.next(token))
        throw InputError(m_file, at_line(line_number), "vertex has fewer than 3 coordinates");
      if (!parse_double(token, p[k]))
        throw InputError(m_file, at_line(line_number),
                         "vertex coordinate '" + std::string(token) + "' is not a number");
      if (!std::isfinite(p[k]))
        throw InputError(
            m_file, at_line(line_number),
            "vertex " + std::to_string(m_parsed.mesh.positions.size()) + " has a non-finite coordinate");
    }
    return p;
  }

  void face(Tokens& tokens, std::size_t line_number) {
    ObjMesh& mesh = m_parsed.mesh;
    const std::size_t first = m_parsed.corners.size();
    std::string_view token;
    while (tokens.next(token)) {
      const std::size_t slash = token.find('/');
      Corner c{m_vertex_index.resolve(token.substr(0, slash), std::int64_t(mesh.positions.size()), m_file,
                                      line_number, token),
               -1, -1};
      if (slash != std::string_view::npos) {
        const std::string_view rest = token.substr(slash + 1);
        const std::size_t second = rest.find('/');
        const std::string_view t = rest.substr(0, second);
        if (!t.empty())
          c.t = m_texcoord_index.resolve(t, std::int64_t(mesh.texcoords.size()), m_file, line_number, token);
        if (second != std::string_view::npos && second + 1 < rest.size())
          c.n = m_normal_index.resolve(rest.substr(second + 1), std::int64_t(mesh.normals.size()), m_file,
                                       line_number, token);
      }
      m_parsed.corners.push_back(c);
      mesh.polygon_corners.push_back(Index(c.v));
    }
    const std::size_t count = m_parsed.corners.size() - first;
    if (count < 3)
      throw InputError(m_file, at_line(line_number),
                       "face has " + std::to_string(count) + " corners, needs 3");
    mesh.polygon_starts.push_back(m_parsed.corners.size());
    ++mesh.num_polygons;
  }

  std::string m_file;
  ParsedObj m_parsed = starting_parse();
  IndexList m_vertex_index{"vertex", "vertices"};
  IndexList m_texcoord_index{"texture coordinate", "texture coordinates"};
  IndexList m_normal_index{"normal", "normals"};
};

// Refuses what is not OBJ text: UTF-16 (a byte-order mark, or the NUL bytes of ASCII in UTF-16) or binary
// data (any NUL byte), naming the byte.
void refuse_what_is_not_text(const std::string& file, const std::string& text) {
  const auto byte = [&](std::size_t i) {
    return i < text.size() ? static_cast<unsigned char>(text[i]) : 256u;
  };
  const bool bom16 = (byte(0) == 0xFF && byte(1) == 0xFE) || (byte(0) == 0xFE && byte(1) == 0xFF);
  const bool le16 = byte(0) != 0 && byte(1) == 0 && byte(2) != 0 && byte(3) == 0;  // ASCII as UTF-16
  const bool be16 = byte(0) == 0 && byte(1) != 0 && byte(2) == 0 && byte(3) != 0;
  const std::size_t nul = text.find('\0');
  if (bom16 || le16 || be16)
    throw InputError(file, "byte 0",
                     "a UTF-16 text file, not an OBJ pleat can read: save it as UTF-8 (or ASCII) text");
  if (nul != std::string::npos) {
    std::string kind = "a binary file, not OBJ text (byte " + std::to_string(nul) + " is 0x00)";
    if (text.compare(0, 4, "glTF") == 0) kind = "a binary glTF (.glb), not OBJ text (rename it .glb)";
    if (text.compare(0, 11, "POINTCACHE2") == 0)
      kind = "a PC2 point cache, not OBJ text (give it as --cache)";
    throw InputError(file, "byte " + std::to_string(nul), kind);
  }
}

ParsedObj parse_obj(const std::filesystem::path& path) {
  ObjParser parser(path.string());
  const std::string text = read_whole_file(path);
  refuse_what_is_not_text(path.string(), text);
  parser.parse(text);
  return parser.finish();
}

// The triangles of every polygon in its plane (polygon_triangulation.hpp), with their corners' attributes.
void triangulate(ParsedObj& parsed) {
  ObjMesh& mesh = parsed.mesh;
  const auto add = [&](std::size_t first, const std::array<std::size_t, 3>& triangle) {
    mesh.triangles.push_back({Index(parsed.corners[first + triangle[0]].v),
                              Index(parsed.corners[first + triangle[1]].v),
                              Index(parsed.corners[first + triangle[2]].v)});
    for (std::size_t k : triangle) {
      mesh.corner_texcoords.push_back(parsed.corners[first + k].t);
      mesh.corner_normals.push_back(parsed.corners[first + k].n);
    }
  };
  std::vector<glm::dvec3> points;
  for (std::size_t p = 0; p < mesh.num_polygons; ++p) {
    const std::size_t first = mesh.polygon_starts[p], last = mesh.polygon_starts[p + 1];
    if (last - first == 3) {  // a triangle, as it is
      add(first, {0, 1, 2});
      continue;
    }
    points.clear();
    for (std::size_t k = first; k < last; ++k)
      points.push_back(mesh.positions[std::size_t(parsed.corners[k].v)]);
    for (const auto& triangle : triangulate_polygon(points)) add(first, triangle);
  }
}

}  // namespace

ObjMesh read_obj(const std::filesystem::path& path) {
  ParsedObj parsed = parse_obj(path);
  triangulate(parsed);
  return std::move(parsed.mesh);
}

ObjMesh read_obj_polygons(const std::filesystem::path& path) { return parse_obj(path).mesh; }

SurfaceAttributes surface_of(const ObjMesh& mesh) {
  SurfaceAttributes surface;
  const auto all_given = [](const std::vector<std::int64_t>& corners) {
    return !corners.empty() &&
           std::all_of(corners.begin(), corners.end(), [](std::int64_t i) { return i >= 0; });
  };
  if (all_given(mesh.corner_texcoords))
    for (std::int64_t t : mesh.corner_texcoords) {
      const glm::dvec2 uv = mesh.texcoords[std::size_t(t)];
      surface.texcoords.emplace_back(float(uv.x), float(1.0 - uv.y));  // OBJ's v runs up, glTF's down
    }
  if (all_given(mesh.corner_normals))
    for (std::int64_t n : mesh.corner_normals) surface.normals.emplace_back(mesh.normals[std::size_t(n)]);
  return surface;
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

namespace {

/// An .obj: one frame, or the frames of its cache (by the cache formats' table), named after the cache then
/// (frame-level errors, NaN or truncation, are about its bytes).
MeshSequence open_obj(const std::filesystem::path& input, const std::filesystem::path& cache,
                      const LoadOptions& options) {
  const std::string name = input.string();
  ObjMesh mesh = read_obj(input);
  const auto num_vertices = Index(mesh.positions.size());
  SurfaceAttributes surface = surface_of(mesh);
  if (cache.empty()) {
    std::vector<std::vector<glm::dvec3>> frames;
    frames.push_back(std::move(mesh.positions));
    return MeshSequence(name, std::move(mesh.triangles), num_vertices,
                        make_memory_source(std::move(frames), {0.0}), options.scan, std::move(surface));
  }
  std::unique_ptr<FrameSource> source = open_cache_for(cache, num_vertices, name, options.scene_fps);
  return MeshSequence(cache.string(), std::move(mesh.triangles), num_vertices, std::move(source),
                      options.scan, std::move(surface));
}

}  // namespace

namespace formats {
extern const MeshFormat kObj{".obj", ".obj [+ .pc2/.mdd cache]", "", nullptr, open_obj, nullptr};
}  // namespace formats

}  // namespace pleat
