// Sky visibility of a flat sheet 1 above the ground y = 0, through the installed library: the upper side
// sees the whole sky (A = 1), the lower one only the sliver between the ground's far edge and the horizon.
#include <cmath>
#include <cstdio>
#include <vector>

#include "kinetic/engine.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/scene.hpp"
#include "sim_io/sequence_plan.hpp"

int main() {
  using namespace pleat;
  const int n = 6;  // n x n vertices over [0, 1]^2 at y = 1, wound so that the front faces +y
  MeshTopology topology;
  topology.num_vertices = n * n;
  Frame frame;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) frame.positions.push_back({double(i) / (n - 1), 1.0, double(j) / (n - 1)});
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const Index a = i * n + j, b = a + 1, c = a + n, d = c + 1;
      topology.triangles.push_back({a, b, d});
      topology.triangles.push_back({a, d, c});
    }
  const MeshSequence cloth("sheet", topology, {frame});
  const Scene scene(cloth, std::vector<OccluderSpec>{}, {GroundPlane{1, 0.0}});
  Engine engine(scene.topology(), PlanOptions{}.make(cloth), {EngineKind::Kinetic});
  const FrameVisibility& vis = engine.compute(scene.frame(0));
  const Index centre = (n / 2) * n + n / 2;
  const double front = vis.measure(Side::Front, centre).sky_visibility;
  const double back = vis.measure(Side::Back, centre).sky_visibility;
  std::printf("consumer: sheet centre: front %.6f back %.6f\n", front, back);
  return std::abs(front - 1.0) < 1e-9 && back >= 0.0 && back < 1e-3 ? 0 : 1;
}
