#include "sim_io/mesh_sequence.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "static_core/slicing_plan.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

class MemorySource : public FrameSource {
 public:
  MemorySource(std::vector<std::vector<glm::dvec3>> frames, std::vector<double> times)
      : m_frames(std::move(frames)), m_times(std::move(times)) {}
  std::size_t num_frames() const override { return m_frames.size(); }
  double frame_time(std::size_t i) const override { return m_times.at(i); }
  std::vector<glm::dvec3> read_frame(std::size_t i) const override { return m_frames.at(i); }

 private:
  std::vector<std::vector<glm::dvec3>> m_frames;
  std::vector<double> m_times;
};

// Bit pattern of a coordinate with -0 and +0 made equal, so that exactly coinciding positions hash alike.
std::uint64_t coordinate_bits(double c) { return std::bit_cast<std::uint64_t>(c == 0.0 ? 0.0 : c); }

struct WeldKey {
  Index cls;
  std::uint64_t x, y, z;
  bool operator==(const WeldKey&) const = default;
};

struct WeldKeyHash {
  std::size_t operator()(const WeldKey& k) const {
    std::uint64_t h = 0x9E3779B97F4A7C15ull * (k.cls + 1);
    for (std::uint64_t v : {k.x, k.y, k.z}) {
      h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
      h *= 0xBF58476D1CE4E5B9ull;
    }
    return std::size_t(h ^ (h >> 31));
  }
};

std::string frame_place(std::size_t i) { return "frame " + std::to_string(i); }

void check_frame_size(const std::string& name, std::size_t frame, std::size_t got, Index expected) {
  if (got != expected)
    throw InputError(name, frame_place(frame),
                     "vertex-count mismatch: the frame has " + std::to_string(got) +
                         " vertices, the mesh has " + std::to_string(expected));
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// Every coordinate finite and within kMaxCoordinate (mesh_sequence.hpp).
void check_coordinates(const std::string& name, std::size_t frame, const std::vector<glm::dvec3>& positions) {
  for (std::size_t v = 0; v < positions.size(); ++v)
    for (int k = 0; k < 3; ++k) {
      const double c = positions[v][k];
      if (!std::isfinite(c))
        throw InputError(name, frame_place(frame) + ", vertex " + std::to_string(v), "non-finite coordinate");
      if (std::abs(c) > kMaxCoordinate)
        throw InputError(
            name, frame_place(frame) + ", vertex " + std::to_string(v),
            "coordinate " + number(c) +
                " beyond +-2^53, where doubles stop holding every integer (an exploded simulation, "
                "or a transform far from the origin?)");
    }
}

// The cloth at least kMinExtent across (mesh_sequence.hpp): `bounds` of every frame.
void check_extent(const std::string& name, const Bounds& bounds) {
  const glm::dvec3 d = bounds.hi - bounds.lo;
  const double extent = std::max({d.x, d.y, d.z});
  if (!(extent >= kMinExtent))
    throw InputError(name, "",
                     extent > 0
                         ? "the mesh spans only " + number(extent) + " (less than " + number(kMinExtent) +
                               ": pleat's double arithmetic would underflow; scale the scene up)"
                         : "the mesh has no extent: every vertex lies at one point in every frame");
}

// Frame times (finite, increasing strictly) and source frame numbers.
void read_times(const std::string& name, const FrameSource& frames, std::vector<double>& times,
                std::vector<std::int64_t>& source_frames) {
  const std::size_t num_frames = frames.num_frames();
  times.resize(num_frames);
  source_frames.resize(num_frames);
  for (std::size_t i = 0; i < num_frames; ++i) {
    times[i] = frames.frame_time(i);
    if (!std::isfinite(times[i])) throw InputError(name, frame_place(i), "frame time is not finite");
    source_frames[i] = frames.source_frame(i);
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InputError(name, frame_place(i), "frame times must increase strictly");
  }
}

}  // namespace

std::unique_ptr<FrameSource> make_memory_source(std::vector<std::vector<glm::dvec3>> frames,
                                                std::vector<double> times) {
  if (frames.size() != times.size()) throw std::invalid_argument("make_memory_source: one time per frame");
  return std::make_unique<MemorySource>(std::move(frames), std::move(times));
}

struct MeshSequence::Impl {
  std::string name;
  MeshTopology topology;
  std::vector<Triangle> input_triangles;
  Index num_input_vertices = 0;
  std::vector<Index> welded_of_input;
  std::vector<Index> input_of_welded;  // one representative input vertex per welded vertex
  std::size_t removed_faces = 0;
  SurfaceAttributes surface;
  std::vector<double> times;
  std::vector<std::int64_t> source_frames;
  Bounds bounds;
  std::unique_ptr<FrameSource> source;
};

MeshSequence::MeshSequence(std::string name, std::vector<Triangle> input_triangles, Index num_input_vertices,
                           std::unique_ptr<FrameSource> frames, const LoadScan& scan,
                           SurfaceAttributes surface) {
  auto impl = std::make_shared<Impl>();
  impl->name = std::move(name);
  const std::string& n = impl->name;
  if (!frames) throw std::invalid_argument("MeshSequence: no frame source");
  for (std::size_t size : {surface.texcoords.size(), surface.normals.size()})
    if (size != 0 && size != 3 * input_triangles.size())
      throw std::invalid_argument("MeshSequence: surface attributes need one value per triangle corner");
  impl->surface = std::move(surface);
  if (num_input_vertices == 0) throw InputError(n, "", "empty mesh: no vertices");
  if (input_triangles.empty()) throw InputError(n, "", "empty mesh: no faces");
  for (std::size_t f = 0; f < input_triangles.size(); ++f)
    for (Index v : input_triangles[f])
      if (v >= num_input_vertices)
        throw InputError(n, "face " + std::to_string(f),
                         "vertex index " + std::to_string(v) + " out of range (" +
                             std::to_string(num_input_vertices) + " vertices)");
  const std::size_t num_frames = frames->num_frames();
  if (num_frames == 0) throw InputError(n, "", "no frames");
  read_times(n, *frames, impl->times, impl->source_frames);

  // Welding by partition refinement: two input vertices stay in one class while they coincide in every
  // frame read so far. Every frame is read once (validating it) even after no class can split any more.
  // With a LoadScan, this process reads only its share of the frames and scan.merge combines the classes.
  std::vector<char> used(num_input_vertices, 0);  // by a triangle: only those stretch bounds()
  for (const Triangle& t : input_triangles)
    for (Index v : t) used[v] = 1;
  std::vector<Index> cls(num_input_vertices, 0);
  Index num_classes = 1;
  std::unordered_map<WeldKey, Index, WeldKeyHash> next;
  std::exception_ptr scan_error;
  try {
    const auto [scan_first, scan_last] =
        scan.range ? scan.range(num_frames) : std::pair<std::size_t, std::size_t>(0, num_frames);
    for (std::size_t i = scan_first; i < std::min(num_frames, scan_last); ++i) {
      const std::vector<glm::dvec3> positions = frames->read_frame(i);
      check_frame_size(n, i, positions.size(), num_input_vertices);
      check_coordinates(n, i, positions);
      if (scan.on_frame) scan.on_frame(i, positions);
      for (Index v = 0; v < num_input_vertices; ++v)
        if (used[v]) impl->bounds.add(positions[v]);
      if (num_classes == num_input_vertices) continue;
      next.clear();
      next.reserve(num_input_vertices);
      for (Index v = 0; v < num_input_vertices; ++v) {
        const glm::dvec3& p = positions[v];
        const WeldKey key{cls[v], coordinate_bits(p.x), coordinate_bits(p.y), coordinate_bits(p.z)};
        cls[v] = next.try_emplace(key, Index(next.size())).first->second;
      }
      num_classes = Index(next.size());
    }
  } catch (...) {
    if (!scan.merge) throw;
    scan_error = std::current_exception();
  }
  if (scan.merge) {
    scan.merge(cls, scan_error);
    num_classes = cls.empty() ? 0 : *std::max_element(cls.begin(), cls.end()) + 1;
  }
  if (scan.merge_bounds) scan.merge_bounds(impl->bounds);
  check_extent(n, impl->bounds);
  // Welded vertices numbered by first appearance in input order.
  std::vector<Index> welded_of_class(num_classes, Index(-1));
  impl->welded_of_input.resize(num_input_vertices);
  for (Index v = 0; v < num_input_vertices; ++v) {
    Index& w = welded_of_class[cls[v]];
    if (w == Index(-1)) {
      w = Index(impl->input_of_welded.size());
      impl->input_of_welded.push_back(v);
    }
    impl->welded_of_input[v] = w;
  }
  impl->topology.num_vertices = Index(impl->input_of_welded.size());

  // Faces over welded vertices: drop collapsed ones and repeats of a face on the same three vertices.
  struct TripleHash {
    std::size_t operator()(const Triangle& t) const {
      return std::size_t(t[0]) * 0x9E3779B97F4A7C15ull ^ std::size_t(t[1]) * 0xC2B2AE3D27D4EB4Full ^ t[2];
    }
  };
  std::unordered_set<Triangle, TripleHash> seen;
  seen.reserve(input_triangles.size());
  for (const Triangle& t : input_triangles) {
    const Triangle w = {impl->welded_of_input[t[0]], impl->welded_of_input[t[1]],
                        impl->welded_of_input[t[2]]};
    Triangle sorted = w;
    std::sort(sorted.begin(), sorted.end());
    if (sorted[0] == sorted[1] || sorted[1] == sorted[2] || !seen.insert(sorted).second) {
      ++impl->removed_faces;
      continue;
    }
    impl->topology.triangles.push_back(w);
  }
  if (impl->topology.triangles.empty())
    throw InputError(n, "", "empty mesh: every face collapses after welding");
  impl->input_triangles = std::move(input_triangles);
  impl->num_input_vertices = num_input_vertices;
  impl->source = std::move(frames);
  m_impl = std::move(impl);
}

MeshSequence::MeshSequence(std::string name, MeshTopology topology, std::vector<Frame> frames) {
  auto impl = std::make_shared<Impl>();
  impl->name = std::move(name);
  if (frames.empty()) throw std::invalid_argument("MeshSequence: no frames");
  for (const Triangle& t : topology.triangles)
    for (Index v : t)
      if (v >= topology.num_vertices)
        throw std::invalid_argument("MeshSequence: triangle index out of range");
  std::vector<std::vector<glm::dvec3>> positions;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].positions.size() != topology.num_vertices)
      throw std::invalid_argument("MeshSequence: frame " + std::to_string(i) + " has the wrong vertex count");
    if (i > 0 && !(frames[i].time > frames[i - 1].time))
      throw std::invalid_argument("MeshSequence: frame times must increase strictly");
    impl->times.push_back(frames[i].time);
    impl->source_frames.push_back(std::int64_t(i));
    impl->bounds.add(cloth_bounds(topology, frames[i]));
    positions.push_back(std::move(frames[i].positions));
  }
  impl->num_input_vertices = topology.num_vertices;
  impl->welded_of_input.resize(topology.num_vertices);
  for (Index v = 0; v < topology.num_vertices; ++v) impl->welded_of_input[v] = v;
  impl->input_of_welded = impl->welded_of_input;
  impl->input_triangles = topology.triangles;
  impl->topology = std::move(topology);
  impl->source = std::make_unique<MemorySource>(std::move(positions), impl->times);
  m_impl = std::move(impl);
}

const std::string& MeshSequence::name() const { return m_impl->name; }
const MeshTopology& MeshSequence::topology() const { return m_impl->topology; }
std::size_t MeshSequence::num_frames() const { return m_impl->times.size(); }

double MeshSequence::frame_rate() const {
  const auto& t = m_impl->times;
  if (t.size() < 2) return 0.0;
  return double(t.size() - 1) / (t.back() - t.front());
}

const Bounds& MeshSequence::bounds() const { return m_impl->bounds; }
double MeshSequence::frame_time(std::size_t i) const { return m_impl->times.at(i); }
std::int64_t MeshSequence::source_frame(std::size_t i) const { return m_impl->source_frames.at(i); }
double MeshSequence::duration() const { return m_impl->times.back() - m_impl->times.front(); }

std::vector<glm::dvec3> MeshSequence::input_positions(std::size_t i) const {
  if (i >= num_frames())
    throw std::out_of_range("MeshSequence: frame " + std::to_string(i) + " out of range");
  std::vector<glm::dvec3> positions = m_impl->source->read_frame(i);
  check_frame_size(m_impl->name, i, positions.size(), m_impl->num_input_vertices);
  return positions;
}

Frame MeshSequence::frame(std::size_t i) const {
  const std::vector<glm::dvec3> input = input_positions(i);
  Frame f;
  f.time = m_impl->times[i];
  f.positions.resize(m_impl->input_of_welded.size());
  for (std::size_t w = 0; w < f.positions.size(); ++w) f.positions[w] = input[m_impl->input_of_welded[w]];
  return f;
}

Index MeshSequence::num_input_vertices() const { return m_impl->num_input_vertices; }
const std::vector<Index>& MeshSequence::welded_of_input() const { return m_impl->welded_of_input; }
std::size_t MeshSequence::welded_duplicates() const {
  return std::size_t(m_impl->num_input_vertices) - m_impl->input_of_welded.size();
}
const std::vector<Triangle>& MeshSequence::input_triangles() const { return m_impl->input_triangles; }
std::size_t MeshSequence::removed_faces() const { return m_impl->removed_faces; }
const SurfaceAttributes& MeshSequence::surface() const { return m_impl->surface; }

}  // namespace pleat
