#include "shading/scene_render.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "static_core/visibility.hpp"

namespace pleat {

namespace {

/// The cloth's part of a scene's topology: its vertices and the triangles before the first occluder's.
MeshTopology cloth_of(const MeshTopology& scene) {
  MeshTopology cloth;
  cloth.num_vertices = scene.num_receivers();
  for (const Triangle& t : scene.triangles) {
    if (t[0] >= cloth.num_vertices || t[1] >= cloth.num_vertices || t[2] >= cloth.num_vertices) break;
    cloth.triangles.push_back(t);
  }
  return cloth;
}

}  // namespace

SceneRenderer::SceneRenderer(const MeshTopology& scene, const glm::dvec3& up, bool draw_occluders)
    : m_drawn(draw_occluders ? scene : cloth_of(scene)), m_cloth_vertices(scene.num_receivers()) {
  if (!(glm::length(up) > 0.0)) throw std::invalid_argument("--up: the world up must not be zero");
  m_up = glm::normalize(up);
  // The ground squares: the vertices of the last num_plane_triangles triangles (sim_io/scene.hpp).
  m_first_ground_vertex = m_drawn.num_vertices;
  for (std::size_t t = m_drawn.triangles.size() - m_drawn.num_plane_triangles; t < m_drawn.triangles.size();
       ++t)
    for (Index v : m_drawn.triangles[t]) m_first_ground_vertex = std::min(m_first_ground_vertex, v);
}

SceneRenderer::~SceneRenderer() = default;

void SceneRenderer::set_frame(const Frame& scene_frame) {
  if (scene_frame.positions.size() < m_drawn.num_vertices)
    throw std::logic_error("SceneRenderer::set_frame: " + std::to_string(scene_frame.positions.size()) +
                           " positions for a scene of " + std::to_string(m_drawn.num_vertices) + " vertices");
  m_frame.time = scene_frame.time;
  m_frame.positions.assign(scene_frame.positions.begin(),
                           scene_frame.positions.begin() + std::ptrdiff_t(m_drawn.num_vertices));
  if (!m_scene)
    m_scene = std::make_unique<EmbreeScene>(m_drawn, m_frame);
  else
    m_scene->update(m_frame);
  m_grey.clear();
  if (m_drawn.num_vertices == m_cloth_vertices) return;
  const std::vector<glm::dvec3> normals = vertex_normals(m_drawn, m_frame);
  for (Index v = m_cloth_vertices; v < m_drawn.num_vertices; ++v) {
    if (v >= m_first_ground_vertex)
      m_grey.push_back({0.78f, 0.75f, 0.70f});
    else
      m_grey.push_back(glm::vec3(float(0.28 + 0.30 * std::abs(glm::dot(normals[v], m_up)))) *
                       glm::vec3(0.90f, 0.95f, 1.0f));
  }
}

std::vector<glm::vec3> SceneRenderer::with_occluders(std::span<const glm::vec3> cloth) const {
  if (cloth.size() != m_cloth_vertices)
    throw std::logic_error("SceneRenderer: " + std::to_string(cloth.size()) + " colours for " +
                           std::to_string(m_cloth_vertices) + " cloth vertices");
  std::vector<glm::vec3> all(cloth.begin(), cloth.end());
  all.insert(all.end(), m_grey.begin(), m_grey.end());
  return all;
}

Image SceneRenderer::render(std::span<const glm::vec3> front_srgb, std::span<const glm::vec3> back_srgb,
                            const Camera& camera, int width, int height) const {
  if (!m_scene) throw std::logic_error("SceneRenderer::render: no frame set");
  return render_image(*m_scene, m_frame, with_occluders(front_srgb), with_occluders(back_srgb), camera, width,
                      height);
}

std::vector<Image> SceneRenderer::turntable_images(std::span<const glm::vec3> front_srgb,
                                                   std::span<const glm::vec3> back_srgb, const Camera& camera,
                                                   int count, int width, int height) const {
  if (!m_scene) throw std::logic_error("SceneRenderer::turntable_images: no frame set");
  return pleat::turntable_images(m_drawn, m_frame, with_occluders(front_srgb), with_occluders(back_srgb),
                                 camera, count, width, height);
}

std::vector<std::filesystem::path> SceneRenderer::turntable(
    const std::filesystem::path& directory, const std::string& stem, std::span<const glm::vec3> front_srgb,
    std::span<const glm::vec3> back_srgb, const Camera& camera, int count, int width, int height) const {
  if (!m_scene) throw std::logic_error("SceneRenderer::turntable: no frame set");
  return render_turntable(directory, stem, m_drawn, m_frame, with_occluders(front_srgb),
                          with_occluders(back_srgb), camera, count, width, height);
}

}  // namespace pleat
