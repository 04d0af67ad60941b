#include "static_core/adaptive_plan.hpp"

#include <algorithm>
#include <glm/geometric.hpp>
#include <vector>

#include "static_core/mesh_connectivity.hpp"
#include "static_core/mesh_slicer.hpp"
#include "static_core/mesh_validation.hpp"

namespace pleat {

SlicingPlan make_adaptive_plan(const MeshTopology& topology, const Frame& frame,
                               const AdaptivePlanParams& params) {
  validate_mesh(topology, frame, "make_adaptive_plan");
  SlicingPlan plan;
  plan.orientations = diffuse_orientations(params.orientations, params.relaxed);
  const MeshConnectivity connectivity(topology);
  const std::size_t n = topology.num_vertices;
  const std::size_t allowed_missing = static_cast<std::size_t>(params.max_missing_fraction * n);
  for (int o = 0; o < static_cast<int>(plan.orientations.size()); ++o) {
    const glm::dvec3 normal = plan.orientations[o];
    std::vector<double> height(n);
    for (std::size_t v = 0; v < n; ++v) height[v] = glm::dot(normal, frame.positions[v]);
    std::vector<char> has_cone(n, 0);
    // Only vertices with at least one incident face can ever receive a cone.
    std::vector<Index> missing;
    for (Index v = 0; v < n; ++v)
      if (!connectivity.is_isolated(v)) missing.push_back(v);
    // Recursive median split, breadth first: each group is the set of still-uncovered vertices
    // between two planes already placed.
    std::vector<std::vector<Index>> groups{missing};
    std::size_t total_missing = missing.size();
    while (total_missing > allowed_missing && !groups.empty()) {
      std::vector<std::vector<Index>> next;
      for (auto& group : groups) {
        if (group.empty()) continue;
        auto mid = group.begin() + group.size() / 2;
        std::nth_element(group.begin(), mid, group.end(),
                         [&](Index a, Index b) { return height[a] < height[b]; });
        const double offset = height[*mid];
        const SlicingPlane plane = make_plane(normal, offset, o);
        plan.planes.push_back(plane);
        for (Index v : cone_recipients(topology, connectivity, frame, plane)) has_cone[v] = 1;
        std::vector<Index> below, above;
        for (Index v : group) {
          if (has_cone[v]) continue;
          (height[v] < offset ? below : above).push_back(v);
        }
        if (!below.empty()) next.push_back(std::move(below));
        if (!above.empty()) next.push_back(std::move(above));
      }
      groups = std::move(next);
      total_missing = 0;
      for (const auto& g : groups) total_missing += g.size();
    }
  }
  return plan;
}

}  // namespace pleat
