#include "shading/cone_cache.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <optional>

#include "support/atomic_file.hpp"
#include "support/byte_order.hpp"
#include "support/checksum.hpp"
#include "support/fingerprint.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

constexpr char kMagic[8] = {'P', 'L', 'E', 'A', 'T', 'C', 'N', 'S'};
constexpr std::uint32_t kExactVersion = 3, kCompactVersion = 4;        // with checksums
constexpr std::uint32_t kOldExactVersion = 1, kOldCompactVersion = 2;  // without, still read
constexpr std::size_t kFixedHeader = 8 + 4 * 6 + 8 + 8;  // magic, six u32, fingerprint, frame rate
constexpr std::size_t kMeasureDoubles = 5;

void append_vec3(std::string& out, const glm::dvec3& v) {
  for (int k = 0; k < 3; ++k) bytes::append_f64_le(out, v[k]);
}

double sign_of(double x) { return x < 0.0 ? -1.0 : 1.0; }

/// The unit direction of two octahedral coordinates, each of [-1, 1] mapped to 0..65535: the point (u, v)
/// of the octahedron |x|+|y|+|z| = 1 seen from above, the lower half folded over the upper one's corners.
glm::dvec3 octahedral_direction(std::uint16_t qu, std::uint16_t qv) {
  const double u = qu / 32767.5 - 1.0, v = qv / 32767.5 - 1.0;
  glm::dvec3 d(u, v, 1.0 - std::abs(u) - std::abs(v));
  if (d.z < 0.0) {
    d.x = (1.0 - std::abs(v)) * sign_of(u);
    d.y = (1.0 - std::abs(u)) * sign_of(v);
  }
  return glm::normalize(d);
}

/// A unit direction's octahedral coordinates: of the four grid points around its exact coordinates, the
/// one whose direction is nearest (rounding each coordinate alone can be 1.4x as far).
void append_octahedral(std::string& out, const glm::dvec3& d) {
  const double l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
  if (!(l1 > 0.0) || !std::isfinite(l1))
    throw std::invalid_argument("cone cache: a cone direction that is zero or not finite");
  double u = d.x / l1, v = d.y / l1;
  if (d.z < 0.0) {
    const double fu = (1.0 - std::abs(v)) * sign_of(u), fv = (1.0 - std::abs(u)) * sign_of(v);
    u = fu;
    v = fv;
  }
  const double gu = (std::clamp(u, -1.0, 1.0) + 1.0) * 32767.5,
               gv = (std::clamp(v, -1.0, 1.0) + 1.0) * 32767.5;
  std::uint16_t best_u = 0, best_v = 0;
  double best = -2.0;
  for (double cu : {std::floor(gu), std::ceil(gu)})
    for (double cv : {std::floor(gv), std::ceil(gv)}) {
      const auto qu = static_cast<std::uint16_t>(cu), qv = static_cast<std::uint16_t>(cv);
      const double closeness = glm::dot(octahedral_direction(qu, qv), d);
      if (closeness > best) {
        best = closeness;
        best_u = qu;
        best_v = qv;
      }
    }
  bytes::append_u16_le(out, best_u);
  bytes::append_u16_le(out, best_v);
}

}  // namespace

const char* cone_encoding_name(ConeEncoding encoding) {
  return encoding == ConeEncoding::Compact ? "compact" : "exact";
}

std::uint64_t topology_fingerprint(const MeshTopology& topology) {
  Fingerprint f;
  for (const Triangle& t : topology.triangles)
    for (Index v : t) f.add_le(v, 4);
  return f.value();
}

std::uint64_t positions_fingerprint(const Frame& frame) {
  Fingerprint f;
  for (const glm::dvec3& p : frame.positions)
    for (int k = 0; k < 3; ++k) f.add_le(std::bit_cast<std::uint64_t>(p[k]), 8);
  return f.value();
}

// ---- Writer ----

struct ConeCacheWriter::Impl {
  AtomicFile file;
  Index vertices = 0;
  ConeEncoding encoding = ConeEncoding::Exact;
  std::size_t frames = 0;
  std::uint64_t table_offset = 0;
  std::string header;  // the bytes before the table, for the checksum
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint32_t> checksums;  // of each frame block
  std::uint64_t position = 0;
  bool closed = false;

  explicit Impl(const std::filesystem::path& path) : file(path) {}

  void write(std::string_view bytes) {
    file.stream().write(bytes.data(), std::streamsize(bytes.size()));
    file.check();
    position += bytes.size();
  }
};

ConeCacheWriter::ConeCacheWriter(const std::filesystem::path& path, const MeshTopology& topology,
                                 std::span<const Index> welded_of_input, double frame_rate, std::string plan,
                                 std::vector<std::uint32_t> frames, ConeEncoding encoding)
    : m_impl(std::make_unique<Impl>(path)) {
  Impl& w = *m_impl;
  w.vertices = topology.num_vertices;
  w.encoding = encoding;
  const std::uint32_t version = encoding == ConeEncoding::Compact ? kCompactVersion : kExactVersion;
  w.frames = frames.size();
  std::string h(kMagic, kMagic + 8);
  const std::size_t table_offset =
      kFixedHeader + 4 + plan.size() + 4 * welded_of_input.size() + 12 * frames.size();
  for (std::size_t value : {std::size_t(version), table_offset, std::size_t(topology.num_vertices),
                            welded_of_input.size(), topology.triangles.size(), frames.size()})
    bytes::append_u32_le(h, std::uint32_t(value));
  bytes::append_u64_le(h, topology_fingerprint(topology));
  bytes::append_f64_le(h, frame_rate);
  bytes::append_u32_le(h, std::uint32_t(plan.size()));
  h += plan;
  for (Index v : welded_of_input) bytes::append_u32_le(h, v);
  for (std::uint32_t f : frames) {
    bytes::append_u32_le(h, f);
    bytes::append_f64_le(h, frame_rate > 0.0 ? f / frame_rate : 0.0);
  }
  w.table_offset = h.size();
  w.header = h;
  // The table, filled in by close(): the offsets, the frames' checksums and the header's.
  h.append(8 * (frames.size() + 1) + 4 * frames.size() + 4, '\0');
  w.write(h);
}

ConeCacheWriter::~ConeCacheWriter() = default;

std::string encode_cone_frame(const Frame& frame, const FrameVisibility& visibility, ConeEncoding encoding) {
  const Index vertices = static_cast<Index>(visibility.normals.size());
  std::string out;
  bytes::append_u64_le(out, positions_fingerprint(frame));
  for (Index v = 0; v < vertices; ++v) append_vec3(out, visibility.normals[v]);
  for (Side side : kBothSides) {
    for (Index v = 0; v < vertices; ++v) {
      const ConeMeasures& m = visibility.measure(side, v);
      bytes::append_f64_le(out, m.sky_visibility);
      append_vec3(out, m.bent_normal);
      bytes::append_f64_le(out, m.solid_angle);
    }
    for (Index v = 0; v < vertices; ++v) {
      const VisibilityCone& cone = visibility.cone(side, v);
      bytes::append_u32_le(out, std::uint32_t(cone.pieces.size()));
      for (const SphericalPolygon& piece : cone.pieces) {
        bytes::append_u32_le(out, std::uint32_t(piece.size()));
        for (const glm::dvec3& d : piece) {
          if (encoding == ConeEncoding::Compact)
            append_octahedral(out, d);
          else
            append_vec3(out, d);
        }
      }
    }
  }
  return out;
}

void ConeCacheWriter::add_frame(const Frame& frame, const FrameVisibility& visibility) {
  if (visibility.normals.size() != m_impl->vertices)
    throw std::invalid_argument("ConeCacheWriter: a frame of another vertex count");
  add_encoded_frame(encode_cone_frame(frame, visibility, m_impl->encoding));
}

void ConeCacheWriter::add_encoded_frame(std::string_view block) {
  Impl& w = *m_impl;
  if (w.offsets.size() == w.frames) throw std::logic_error("ConeCacheWriter: more frames than announced");
  // The fixed part: fingerprint, normals, and per side the measures and a piece count per vertex.
  const std::uint64_t least = 8 + std::uint64_t(w.vertices) * (24 + 2 * (8 * kMeasureDoubles + 4));
  if (block.size() < least)
    throw std::invalid_argument("ConeCacheWriter: a frame block too short for the mesh");
  w.offsets.push_back(w.position);
  w.checksums.push_back(checksum(block));
  w.write(block);
}

void ConeCacheWriter::close() {
  Impl& w = *m_impl;
  if (w.closed) return;
  if (w.offsets.size() != w.frames) throw std::logic_error("ConeCacheWriter: frames missing at commit");
  w.offsets.push_back(w.position);
  std::string table;
  for (std::uint64_t offset : w.offsets) bytes::append_u64_le(table, offset);
  for (std::uint32_t sum : w.checksums) bytes::append_u32_le(table, sum);
  bytes::append_u32_le(table, Checksum().add(w.header).add(table).value());
  std::ostream& out = w.file.stream();
  out.seekp(std::streamoff(w.table_offset));
  out.write(table.data(), std::streamsize(table.size()));
  w.file.check();
  w.file.close();
  w.closed = true;
}

void ConeCacheWriter::commit() {
  close();
  m_impl->file.commit();
}

// ---- Reader ----

struct ConeCacheReader::Impl {
  std::string path;
  std::ifstream in;
  std::uint64_t file_size = 0;
  bool checksummed = false;  // versions 3 and 4
  ConeCacheHeader header;
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint32_t> checksums;  // of each frame block
  std::string block;

  [[noreturn]] void fail(const std::string& place, const std::string& what) const {
    throw InputError(path, place, what);
  }

  /// Reads `n` bytes at `offset` into `block`, or fails naming `place`.
  const unsigned char* read(std::uint64_t offset, std::uint64_t n, const std::string& place) {
    if (offset > file_size || n > file_size - offset)
      fail(place, "truncated cone cache: needs bytes up to " + std::to_string(offset + n) +
                      ", the file has " + std::to_string(file_size));
    block.resize(n);
    in.seekg(std::streamoff(offset));
    in.read(block.data(), std::streamsize(n));
    if (!in) fail(place, "cannot read the cone cache");
    return reinterpret_cast<const unsigned char*>(block.data());
  }
  /// Cached frame `index` into `out`; `frame`, when given, must be the positions it was computed for.
  void read_frame(std::size_t index, const Frame* frame, FrameVisibility& out);

  /// The magic, the version and the table's offset; the header's counts into `header`.
  std::uint64_t read_fixed_header(std::uint32_t& frames, std::uint32_t& input_vertices);
  /// The plan, the input's vertex map and the frame list (`p`: the bytes from kFixedHeader to the table).
  void read_lists(const unsigned char* p, std::uint64_t table_offset, std::uint32_t frames,
                  std::uint32_t input_vertices);
  /// The frame table at `p` (`frames` + 1 offsets, and with checksums each frame's).
  void read_table(const unsigned char* p, std::uint64_t table_offset, std::uint32_t frames);
};

std::uint64_t ConeCacheReader::Impl::read_fixed_header(std::uint32_t& frames, std::uint32_t& input_vertices) {
  const unsigned char* p = read(0, kFixedHeader, "byte 0");
  if (std::memcmp(p, kMagic, 8) != 0) fail("byte 0", "not a pleat cone cache (no \"PLEATCNS\" magic)");
  const std::uint32_t version = bytes::load_u32_le(p + 8);
  if (version != kExactVersion && version != kCompactVersion && version != kOldExactVersion &&
      version != kOldCompactVersion)
    fail("byte 8", "cone cache version " + std::to_string(version) + " (this pleat reads versions 1 to 4)");
  checksummed = version == kExactVersion || version == kCompactVersion;
  const std::uint64_t table_offset = bytes::load_u32_le(p + 12);
  ConeCacheHeader& h = header;
  h.encoding = version == kCompactVersion || version == kOldCompactVersion ? ConeEncoding::Compact
                                                                           : ConeEncoding::Exact;
  h.vertices = bytes::load_u32_le(p + 16);
  input_vertices = bytes::load_u32_le(p + 20);
  h.triangles = bytes::load_u32_le(p + 24);
  frames = bytes::load_u32_le(p + 28);
  h.fingerprint = bytes::load_u64_le(p + 32);
  h.frame_rate = bytes::load_f64_le(p + 40);
  return table_offset;
}

void ConeCacheReader::Impl::read_lists(const unsigned char* p, std::uint64_t table_offset,
                                       std::uint32_t frames, std::uint32_t input_vertices) {
  ConeCacheHeader& h = header;
  if (!std::isfinite(h.frame_rate) || h.frame_rate < 0.0) fail("byte 40", "invalid frame rate");
  const std::uint64_t expected_table =
      kFixedHeader + 4 + 4 * std::uint64_t(input_vertices) + 12 * std::uint64_t(frames);
  if (table_offset < expected_table) fail("byte 12", "the frame table overlaps the header");
  const std::string place = "byte " + std::to_string(kFixedHeader);
  const std::uint32_t plan_bytes = bytes::load_u32_le(p);
  if (kFixedHeader + 4 + std::uint64_t(plan_bytes) + 4 * std::uint64_t(input_vertices) +
          12 * std::uint64_t(frames) !=
      table_offset)
    fail(place, "the header's sizes do not add up to the frame table's offset");
  h.plan.assign(reinterpret_cast<const char*>(p + 4), plan_bytes);
  p += 4 + plan_bytes;
  h.welded_of_input.resize(input_vertices);
  for (std::uint32_t i = 0; i < input_vertices; ++i) {
    h.welded_of_input[i] = bytes::load_u32_le(p + 4 * i);
    if (h.welded_of_input[i] >= h.vertices)
      fail(place, "input vertex " + std::to_string(i) + " maps to no vertex");
  }
  p += 4 * std::uint64_t(input_vertices);
  for (std::uint32_t k = 0; k < frames; ++k) {
    h.frames.push_back(bytes::load_u32_le(p + 12 * k));
    h.times.push_back(bytes::load_f64_le(p + 12 * k + 4));
  }
}

void ConeCacheReader::Impl::read_table(const unsigned char* p, std::uint64_t table_offset,
                                       std::uint32_t frames) {
  for (std::uint32_t k = 0; k <= frames; ++k) offsets.push_back(bytes::load_u64_le(p + 8 * k));
  if (checksummed)
    for (std::uint32_t k = 0; k < frames; ++k)
      checksums.push_back(bytes::load_u32_le(p + 8 * (std::uint64_t(frames) + 1) + 4 * k));
  const std::uint64_t data_start =
      table_offset + 8 * (std::uint64_t(frames) + 1) + (checksummed ? 4 * std::uint64_t(frames) + 4 : 0);
  for (std::uint32_t k = 0; k < frames; ++k)
    if (offsets[k] < data_start || offsets[k + 1] < offsets[k])
      fail("frame table", "frame " + std::to_string(k) + "'s offsets are out of order");
  if (offsets.back() != file_size)
    fail("frame table", "truncated cone cache: the frames end at byte " + std::to_string(offsets.back()) +
                            ", the file has " + std::to_string(file_size) + " bytes");
}

ConeCacheReader::ConeCacheReader(const std::filesystem::path& path) : m_impl(std::make_unique<Impl>()) {
  Impl& r = *m_impl;
  r.path = path.string();
  r.in.open(path, std::ios::binary);
  if (!r.in) r.fail("", "cannot open the cone cache");
  std::error_code error;
  r.file_size = std::filesystem::file_size(path, error);
  if (error) r.fail("", "cannot read the cone cache's size");
  std::uint32_t frames = 0, input_vertices = 0;
  const std::uint64_t table_offset = r.read_fixed_header(frames, input_vertices);
  if (table_offset < kFixedHeader + 4) r.fail("byte 12", "the frame table overlaps the header");
  const std::uint64_t table_bytes =
      8 * (std::uint64_t(frames) + 1) + (r.checksummed ? 4 * std::uint64_t(frames) + 4 : 0);
  if (r.checksummed) {  // the header and the table, checked before anything in them is believed
    if (table_offset > r.file_size || table_bytes > r.file_size - table_offset)
      r.fail("byte 12",
             "damaged or truncated cone cache: its header puts the frame table past the end of the "
             "file (" +
                 std::to_string(r.file_size) + " bytes)");
    const unsigned char* all = r.read(0, table_offset + table_bytes, "byte 0");
    const std::uint64_t sum_at = table_offset + table_bytes - 4;
    if (Checksum().add(all, sum_at).value() != bytes::load_u32_le(all + sum_at))
      r.fail("bytes 0-" + std::to_string(sum_at),
             "damaged cone cache: the checksum of its header and frame table does not match (the file was "
             "changed or corrupted after pleat wrote it); compute it again (pleat visibility --cones)");
    const std::string verified = std::move(r.block);
    const auto* p = reinterpret_cast<const unsigned char*>(verified.data());
    r.read_lists(p + kFixedHeader, table_offset, frames, input_vertices);
    r.read_table(p + table_offset, table_offset, frames);
    return;
  }
  const unsigned char* p =
      r.read(kFixedHeader, table_offset - kFixedHeader, "byte " + std::to_string(kFixedHeader));
  r.read_lists(p, table_offset, frames, input_vertices);
  r.read_table(r.read(table_offset, table_bytes, "byte " + std::to_string(table_offset)), table_offset,
               frames);
}

ConeCacheReader::~ConeCacheReader() = default;

const ConeCacheHeader& ConeCacheReader::header() const { return m_impl->header; }

void ConeCacheReader::check_mesh(const MeshTopology& topology, std::span<const Index> welded_of_input) const {
  const ConeCacheHeader& h = m_impl->header;
  auto mismatch = [&](const std::string& what) {
    m_impl->fail("", "the cone cache was computed for a different mesh (" + what + ")");
  };
  if (h.vertices != topology.num_vertices)
    mismatch(std::to_string(h.vertices) + " vertices, this mesh has " +
             std::to_string(topology.num_vertices));
  if (h.triangles != topology.triangles.size())
    mismatch(std::to_string(h.triangles) + " triangles, this mesh has " +
             std::to_string(topology.triangles.size()));
  if (h.fingerprint != topology_fingerprint(topology)) mismatch("other triangles");
  if (!std::equal(h.welded_of_input.begin(), h.welded_of_input.end(), welded_of_input.begin(),
                  welded_of_input.end()))
    mismatch("another vertex order");
}

std::size_t ConeCacheReader::index_of_frame(std::size_t frame) const {
  const auto& frames = m_impl->header.frames;
  for (std::size_t k = 0; k < frames.size(); ++k)
    if (frames[k] == frame) return k;
  m_impl->fail("frame " + std::to_string(frame),
               "this frame is not in the cone cache (it has " + std::to_string(frames.size()) + " frames)");
}

void ConeCacheReader::read_frame(std::size_t index, const Frame& frame, FrameVisibility& out) {
  m_impl->read_frame(index, &frame, out);
}

void ConeCacheReader::read_frame_unchecked(std::size_t index, FrameVisibility& out) {
  m_impl->read_frame(index, nullptr, out);
}

void ConeCacheReader::Impl::read_frame(std::size_t index, const Frame* frame, FrameVisibility& out) {
  Impl& r = *this;
  const Index n = r.header.vertices;
  const std::string place = "frame " + std::to_string(r.header.frames.at(index));
  const std::uint64_t start = r.offsets[index], size = r.offsets[index + 1] - start;
  const unsigned char* p = r.read(start, size, place);
  if (r.checksummed && Checksum().add(p, size).value() != r.checksums[index])
    r.fail(place + ", bytes " + std::to_string(start) + "-" + std::to_string(start + size - 1),
           "damaged cone cache: the frame's checksum does not match (the file was changed or corrupted after "
           "pleat wrote it); compute it again (pleat visibility --cones)");
  const unsigned char* const end = p + size;
  auto need = [&](std::uint64_t bytes) {
    if (std::uint64_t(end - p) < bytes)
      r.fail(place + ", byte " + std::to_string(start + (size - std::uint64_t(end - p))),
             "the frame block ends early");
  };
  auto number = [&] {
    const double x = bytes::load_f64_le(p);
    if (!std::isfinite(x))
      r.fail(place + ", byte " + std::to_string(start + (size - std::uint64_t(end - p))),
             "a number is not finite");
    p += 8;
    return x;
  };
  auto vec3 = [&] {
    glm::dvec3 v;
    for (int k = 0; k < 3; ++k) v[k] = number();
    return v;
  };
  need(8);
  if (frame != nullptr && bytes::load_u64_le(p) != positions_fingerprint(*frame))
    r.fail(place, "the cones were computed for other positions of this frame (a different simulation)");
  p += 8;
  need(24 * std::uint64_t(n));
  out.normals.resize(n);
  for (Index v = 0; v < n; ++v) out.normals[v] = vec3();
  for (int side = 0; side < 2; ++side) {
    need(8 * kMeasureDoubles * std::uint64_t(n));
    out.measures[side].resize(n);
    for (ConeMeasures& m : out.measures[side]) {
      m.sky_visibility = number();
      m.bent_normal = vec3();
      m.solid_angle = number();
    }
    out.cones[side].resize(n);
    for (VisibilityCone& cone : out.cones[side]) {
      need(4);
      const std::uint32_t pieces = bytes::load_u32_le(p);
      p += 4;
      need(4 * std::uint64_t(pieces));  // at least a count per piece
      cone.pieces.resize(pieces);
      for (SphericalPolygon& piece : cone.pieces) {
        need(4);
        const std::uint32_t k = bytes::load_u32_le(p);
        p += 4;
        need((r.header.encoding == ConeEncoding::Compact ? 4 : 24) * std::uint64_t(k));  // before allocating
        piece.resize(k);
        if (r.header.encoding == ConeEncoding::Compact) {
          for (glm::dvec3& d : piece) {
            d = octahedral_direction(bytes::load_u16_le(p), bytes::load_u16_le(p + 2));
            p += 4;
          }
        } else {
          for (glm::dvec3& d : piece) d = vec3();
        }
      }
    }
  }
  if (p != end) r.fail(place, "the frame block has " + std::to_string(end - p) + " bytes too many");
  out.stats = {};
}

}  // namespace pleat
