#include "sim_io/scene.hpp"

#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "sim_io/load_sequence.hpp"
#include "static_core/slicing_plan.hpp"
#include "support/input_error.hpp"

namespace pleat {

OccluderSpec parse_occluder_spec(std::string_view text) {
  OccluderSpec spec;
  const std::size_t comma = text.rfind(",cache=");
  spec.path = std::string(text.substr(0, comma));
  if (comma != std::string_view::npos) spec.cache = std::string(text.substr(comma + 7));
  if (spec.path.empty() || (comma != std::string_view::npos && spec.cache.empty()))
    throw std::invalid_argument("--occluder: '" + std::string(text) + "' is not PATH or PATH,cache=CACHE");
  return spec;
}

GroundPlane parse_ground_plane(std::string_view text) {
  const auto bad = [&] {
    return std::invalid_argument(
        "--ground: '" + std::string(text) +
        "' is not AXIS=VALUE or -AXIS=VALUE (e.g. y=0, z=0, -y=2.5 for a solid above)");
  };
  GroundPlane ground;
  std::string_view rest = text;
  if (!rest.empty() && (rest[0] == '-' || rest[0] == '+')) {
    ground.up = rest[0] == '-' ? -1.0 : 1.0;
    rest.remove_prefix(1);
  }
  if (rest.size() < 3 || rest[1] != '=' || (rest[0] != 'x' && rest[0] != 'y' && rest[0] != 'z')) throw bad();
  ground.axis = rest[0] - 'x';
  const std::string value(rest.substr(2));
  std::size_t used = 0;
  try {
    ground.height = std::stod(value, &used);
  } catch (const std::exception&) {
    throw bad();
  }
  if (used != value.size() || !std::isfinite(ground.height)) throw bad();
  return ground;
}

Scene::Scene(const MeshSequence& cloth) : m_cloth(&cloth), m_topology(cloth.topology()) {}

namespace {

std::vector<Scene::LoadedOccluder> load_occluders(const std::vector<OccluderSpec>& specs) {
  std::vector<Scene::LoadedOccluder> loaded;
  for (const OccluderSpec& spec : specs)
    loaded.push_back({spec.cache.empty() ? spec.path : spec.cache, load_sequence(spec.path, spec.cache)});
  return loaded;
}

std::string frame_range(const MeshSequence& mesh) {
  const std::int64_t first = mesh.source_frame(0), last = mesh.source_frame(mesh.num_frames() - 1);
  return first == last ? "frame " + std::to_string(first)
                       : "frames " + std::to_string(first) + " to " + std::to_string(last);
}

/// The occluder's frame for each of the cloth's, paired by source frame number (FrameSource::source_frame):
/// an animated occluder must run at the cloth's rate and hold every source frame the cloth holds. Throws
/// InputError naming the occluder, with both ranges, otherwise.
std::vector<std::size_t> pair_frames(const MeshSequence& cloth, const MeshSequence& mesh,
                                     const std::string& name) {
  const std::size_t frames = cloth.num_frames();
  if (frames > 1 && std::abs(mesh.frame_rate() - cloth.frame_rate()) > 1e-6 * cloth.frame_rate())
    throw InputError(name, "",
                     "the occluder runs at " + std::to_string(mesh.frame_rate()) +
                         " frames per second, the cloth at " + std::to_string(cloth.frame_rate()));
  std::vector<std::size_t> paired(frames);
  std::size_t j = 0;  // both number their frames in increasing order
  for (std::size_t i = 0; i < frames; ++i) {
    const std::int64_t number = cloth.source_frame(i);
    while (j < mesh.num_frames() && mesh.source_frame(j) < number) ++j;
    if (j == mesh.num_frames() || mesh.source_frame(j) != number)
      throw InputError(name, "",
                       "the animated occluder has no source frame " + std::to_string(number) + " (it holds " +
                           frame_range(mesh) + " in " + std::to_string(mesh.num_frames()) +
                           " frames, the cloth " + frame_range(cloth) + " in " + std::to_string(frames) +
                           "): an animated occluder needs a frame of the same number for each of the cloth's "
                           "(a static one, a single frame)");
    paired[i] = j;
  }
  return paired;
}

}  // namespace

Scene::Scene(const MeshSequence& cloth, const std::vector<OccluderSpec>& occluders,
             const std::vector<GroundPlane>& grounds, std::optional<double> contact_tolerance)
    : Scene(cloth) {
  add(load_occluders(occluders), grounds, contact_tolerance);
}

Scene Scene::with_loaded(const MeshSequence& cloth, std::vector<LoadedOccluder> occluders,
                         const std::vector<GroundPlane>& grounds, std::optional<double> contact_tolerance) {
  Scene scene(cloth);
  scene.add(std::move(occluders), grounds, contact_tolerance);
  return scene;
}

void Scene::add(std::vector<LoadedOccluder> occluders, const std::vector<GroundPlane>& grounds,
                std::optional<double> contact_tolerance) {
  const MeshSequence& cloth = *m_cloth;
  for (LoadedOccluder& loaded : occluders) {
    Occluder occluder{std::move(loaded.mesh), {}, {}};
    if (occluder.mesh.num_frames() == 1)
      occluder.still = occluder.mesh.frame(0).positions;
    else
      occluder.frame_of = pair_frames(cloth, occluder.mesh, loaded.name);
    m_occluders.push_back(std::move(occluder));
  }
  // Every occluder's triangles over vertices numbered after the cloth's (and the previous occluders').
  for (const Occluder& o : m_occluders) {
    const Index base = m_topology.num_vertices;
    for (const Triangle& t : o.mesh.topology().triangles)
      m_topology.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    m_topology.num_vertices += o.mesh.topology().num_vertices;
  }
  if (contact_tolerance && !(std::isfinite(*contact_tolerance) && *contact_tolerance >= 0.0))
    throw InputError("--contact-tolerance", "", "must be a finite distance >= 0");
  m_topology.contact_tolerance =
      contact_tolerance ? *contact_tolerance : 0.5 * average_edge_length(cloth.topology(), cloth.frame(0));
  const Bounds& box = cloth.bounds();
  const glm::dvec3 centre = 0.5 * (box.lo + box.hi);
  const double half = 50.0 * std::max(glm::length(box.hi - box.lo), 1e-9);
  for (const GroundPlane& g : grounds) {
    const int a = (g.axis + 1) % 3,
              b = (g.axis + 2) % 3;  // (a, b, axis) right-handed: the square faces +axis
    const Index base = m_topology.num_vertices;
    for (const auto& [sa, sb] : {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}}) {
      glm::dvec3 corner(0.0);
      corner[g.axis] = g.height;
      corner[a] = centre[a] + sa * half;
      corner[b] = centre[b] + sb * half;
      m_grounds.push_back(corner);
    }
    if (g.up > 0) {  // the square faces the plane's outer side
      m_topology.triangles.push_back({base, base + 1, base + 2});
      m_topology.triangles.push_back({base, base + 2, base + 3});
    } else {
      m_topology.triangles.push_back({base, base + 2, base + 1});
      m_topology.triangles.push_back({base, base + 3, base + 2});
    }
    m_topology.num_vertices += 4;
    glm::dvec3 normal(0.0);
    normal[g.axis] = g.up;
    m_topology.planes.push_back({normal, normal[g.axis] * g.height});
    m_topology.num_plane_triangles += 2;
  }
  m_topology.num_occluder_vertices = m_topology.num_vertices - cloth.topology().num_vertices;
}

Frame Scene::with_occluders(std::size_t i, Frame frame) const {
  if (m_topology.num_occluder_vertices == 0) return frame;
  frame.positions.reserve(m_topology.num_vertices);
  for (const Occluder& o : m_occluders) {
    if (!o.still.empty()) {
      frame.positions.insert(frame.positions.end(), o.still.begin(), o.still.end());
    } else {
      const Frame moving = o.mesh.frame(o.frame_of.at(i));
      frame.positions.insert(frame.positions.end(), moving.positions.begin(), moving.positions.end());
    }
  }
  frame.positions.insert(frame.positions.end(), m_grounds.begin(), m_grounds.end());
  return frame;
}

}  // namespace pleat
