#include "kinetic/internal/kept_triangulation.hpp"

#include "static_core/assert.hpp"

namespace pleat::kinetic {

void KeptTriangulation::release() {
  vertices = {};
  neighbors = {};
  constrained = {};
}

void keep_triangulation(cgal::Cdt& cdt, KeptTriangulation& out) {
  PLEAT_ASSERT(cdt.dimension() == 2, "only a 2D triangulation is kept");
  cgal::Tds& tds = cdt.tds();
  const std::size_t faces = tds.number_of_faces();
  out.vertices.resize(3 * faces);
  out.neighbors.resize(3 * faces);
  out.constrained.resize(faces);
  int index = 0;
  for (auto f = tds.faces_begin(); f != tds.faces_end(); ++f) f->info().index = index++;
  std::size_t k = 0;
  for (auto f = tds.faces_begin(); f != tds.faces_end(); ++f, ++k) {
    std::uint8_t bits = 0;
    for (int i = 0; i < 3; ++i) {
      const cgal::VertexHandle v = f->vertex(i);
      out.vertices[3 * k + i] = cdt.is_infinite(v) ? -1 : v->info().slice_vertex;
      out.neighbors[3 * k + i] = f->neighbor(i)->info().index;
      bits |= static_cast<std::uint8_t>(f->is_constrained(i)) << i;
    }
    out.constrained[k] = bits;
  }
}

void restore_triangulation(const KeptTriangulation& kept, const Slice& slice, cgal::Cdt& cdt,
                           RestoreScratch& scratch) {
  cdt.clear();
  cgal::Tds& tds = cdt.tds();
  // clear() leaves the infinite vertex alone, in dimension -1, where one face holds it.
  PLEAT_ASSERT(tds.faces().size() == 1, "a cleared triangulation has one face");
  tds.delete_face(tds.faces().begin());
  tds.set_dimension(2);
  const std::size_t n = slice.vertices.size(), faces = kept.num_faces();
  // Vertices in slice-vertex order, faces in the kept order (the containers hand out consecutive slots), then
  // each face's vertices, neighbours and constraints.
  std::vector<cgal::FaceHandle>& face = scratch.faces;
  std::vector<cgal::VertexHandle>& vertex = scratch.vertices;
  face.resize(faces);
  vertex.resize(n);
  for (std::size_t x = 0; x < n; ++x) {
    const cgal::VertexHandle v = tds.create_vertex();
    v->set_point(cgal::to_point(slice.vertices[x].point));
    v->info().slice_vertex = static_cast<int>(x);
    vertex[x] = v;
  }
  for (std::size_t k = 0; k < faces; ++k) face[k] = tds.create_face();
  const cgal::VertexHandle infinite = cdt.infinite_vertex();
  for (std::size_t k = 0; k < faces; ++k) {
    const cgal::FaceHandle f = face[k];
    for (int i = 0; i < 3; ++i) {
      const std::int32_t x = kept.vertices[3 * k + i];
      PLEAT_ASSERT(x < std::int32_t(n), "a kept face names a slice vertex the slice does not have");
      const cgal::VertexHandle v = x < 0 ? infinite : vertex[x];
      f->set_vertex(i, v);
      v->set_face(f);
      f->set_neighbor(i, face[kept.neighbors[3 * k + i]]);
      f->set_constraint(i, (kept.constrained[k] >> i) & 1);
    }
  }
}

}  // namespace pleat::kinetic
