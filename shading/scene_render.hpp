// The cloth drawn in its scene, for the images of `pleat shade --render` and `pleat compare`: the cloth in
// the colours it is given, the occluders (sim_io/scene.hpp: their vertices after the cloth's) in a slate
// grey lit from the world's up direction, (0.28 + 0.30 |n . up|) (0.90, 0.95, 1) (n the vertex normal), and
// the ground squares (the vertices of the last MeshTopology::num_plane_triangles) a light warm grey, so that
// both read as shapes apart from the cloth and from the background.
//
// Preconditions: the scene's topology holds the cloth's vertices first (MeshTopology::num_receivers() of
// them) and the cloth's triangles before the occluders'. Cost: one Embree BVH (built on the first frame,
// updated after) and a vertex-normal pass per frame; each image as render_image (shading/render.hpp).
#pragma once

#include <filesystem>
#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "shading/embree_scene.hpp"
#include "shading/render.hpp"
#include "static_core/mesh.hpp"

namespace pleat {

class SceneRenderer {
 public:
  /// `scene`: the cloth with its occluders (the topology the engines slice). `draw_occluders` false draws
  /// the cloth alone (it is still shaded in its scene). `up`: a non-zero world up.
  SceneRenderer(const MeshTopology& scene, const glm::dvec3& up, bool draw_occluders = true);
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  /// Moves the scene to a frame of it: the cloth's positions, then the occluders' (Scene::with_occluders).
  void set_frame(const Frame& scene_frame);
  /// The image of the frame set last, the cloth in these sRGB colours (one per cloth vertex and side).
  Image render(std::span<const glm::vec3> front_srgb, std::span<const glm::vec3> back_srgb,
               const Camera& camera, int width, int height) const;
  /// turntable_images of the frame set last (shading/render.hpp): `count` images turning about up, in memory.
  std::vector<Image> turntable_images(std::span<const glm::vec3> front_srgb,
                                      std::span<const glm::vec3> back_srgb, const Camera& camera, int count,
                                      int width, int height) const;
  /// render_turntable of the frame set last (shading/render.hpp): `count` images turning about up.
  std::vector<std::filesystem::path> turntable(const std::filesystem::path& directory,
                                               const std::string& stem, std::span<const glm::vec3> front_srgb,
                                               std::span<const glm::vec3> back_srgb, const Camera& camera,
                                               int count, int width, int height) const;

 private:
  /// The cloth's colours, then the occluders' grey when they are drawn.
  std::vector<glm::vec3> with_occluders(std::span<const glm::vec3> cloth) const;

  MeshTopology m_drawn;  ///< the scene, or the cloth alone
  Index m_cloth_vertices = 0;
  Index m_first_ground_vertex = 0;  ///< of m_drawn: the ground squares' vertices are the last
  glm::dvec3 m_up;
  Frame m_frame;                  ///< of m_drawn
  std::vector<glm::vec3> m_grey;  ///< per occluder vertex drawn
  std::unique_ptr<EmbreeScene> m_scene;
};

}  // namespace pleat
