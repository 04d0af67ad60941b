#include "cli/contact_warning.hpp"

#include <algorithm>

namespace pleat::cli {

void ContactWarning::add(std::size_t frame, std::size_t penetrating_vertices, double deepest,
                         Index deepest_vertex) {
  if (penetrating_vertices == 0) return;
  if (m_frames++ == 0 || frame < m_first_frame) {
    m_first_frame = frame;
    m_first_count = penetrating_vertices;
  }
  if (deepest > m_deepest) {
    m_deepest = deepest;
    m_deepest_vertex = deepest_vertex;
    m_deepest_frame = frame;
  }
}

Index input_vertex(const MeshSequence& cloth, Index welded) {
  const auto& of_input = cloth.welded_of_input();
  if (of_input.empty()) return welded;  // an in-memory sequence: not welded
  return static_cast<Index>(std::find(of_input.begin(), of_input.end(), welded) - of_input.begin());
}

void ContactWarning::warn(double tolerance, std::ostream& out) const {
  if (m_frames == 0) return;
  out << "pleat: warning: cloth lies deeper than the contact tolerance (" << tolerance
      << ") inside an occluder or below the ground in " << m_frames << (m_frames == 1 ? " frame" : " frames")
      << " (first: frame " << m_first_frame << ", " << m_first_count
      << (m_first_count == 1 ? " vertex" : " vertices") << "; deepest " << m_deepest << " at vertex "
      << m_deepest_vertex << " in frame " << m_deepest_frame
      << "); those vertices were taken as lying on the surface (--contact-tolerance sets the tolerance; "
         "--stats counts penetrating_vertices per frame)\n";
}

}  // namespace pleat::cli
