// Small in-memory cloth sequences and file helpers shared by the sim_io and `pleat info` tests.
#pragma once

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/pc2_format.hpp"
#include "test_support.hpp"

namespace pleat::test {

/// A (nx x ny)-quad sheet in the xz-plane that folds along x over `frames` frames at 24 fps. Coordinates are
/// rounded to float so that every float32 format stores them exactly (identical counts across formats).
inline MeshSequence folding_sheet(int nx, int ny, int frames) {
  MeshTopology topology;
  topology.num_vertices = Index((nx + 1) * (ny + 1));
  const auto id = [&](int i, int j) { return Index(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      topology.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      topology.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  std::vector<Frame> sequence;
  for (int f = 0; f < frames; ++f) {
    Frame frame;
    frame.time = double(f) / 24.0;
    const double amplitude = 0.3 * double(f) / double(std::max(frames - 1, 1));
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const double x = double(i) / nx, z = double(j) / ny;
        const double y = amplitude * std::sin(3.14159265358979 * x) + 0.05 * z;
        frame.positions.push_back(glm::dvec3(float(x), float(y), float(z)));
      }
    sequence.push_back(std::move(frame));
  }
  return MeshSequence("folding_sheet", std::move(topology), std::move(sequence));
}

/// All welded positions of every frame.
inline std::vector<std::vector<glm::dvec3>> all_positions(const MeshSequence& s) {
  std::vector<std::vector<glm::dvec3>> out;
  for (std::size_t i = 0; i < s.num_frames(); ++i) out.push_back(s.frame(i).positions);
  return out;
}

/// Two triangles that pierce each other in frame 1 only, as DIR/x.obj + DIR/x.pc2 (two frames).
inline void write_piercing_pair(const std::filesystem::path& dir) {
  const MeshTopology t{.num_vertices = 6, .triangles = {{0, 1, 2}, {3, 4, 5}}};
  const std::vector<glm::dvec3> apart = {{0, 0, 0},     {2, 0, 0},     {0, 2, 0},
                                         {0.5, 0.5, 1}, {0.5, 0.5, 2}, {1, 0.5, 1}};
  std::vector<glm::dvec3> pierced = apart;
  pierced[3].z = -1;
  write_obj(dir / "x.obj", t, apart);
  write_pc2(dir / "x.pc2", {apart, pierced}, 0.0, 1.0);
}

inline void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

}  // namespace pleat::test
