// The command line's word on cloth sunk into its colliders (VisibilityStats::penetrating_vertices,
// docs/method.md §6.2): the frames are gathered as they are written, and one warning after the run names the
// first such frame, its count and the deepest vertex (in the input's numbering).
#pragma once

#include <cstddef>
#include <ostream>

#include "sim_io/mesh_sequence.hpp"
#include "static_core/visibility_cone.hpp"

namespace pleat::cli {

/// The first input vertex welded into `welded`.
Index input_vertex(const MeshSequence& cloth, Index welded);

class ContactWarning {
 public:
  /// Notes frame `frame`'s counters (the deepest vertex in the input's numbering).
  void add(std::size_t frame, std::size_t penetrating_vertices, double deepest, Index deepest_vertex);
  /// Writes the warning (nothing when no frame had any) under `tolerance`.
  void warn(double tolerance, std::ostream& out) const;

 private:
  std::size_t m_frames = 0;
  std::size_t m_first_frame = 0, m_first_count = 0;
  double m_deepest = 0.0;
  Index m_deepest_vertex = 0;
  std::size_t m_deepest_frame = 0;
};

}  // namespace pleat::cli
