// The nearest-circle reconstruction (ConeReconstruction::NearestCircle,
// static_core/internal/nearest_circle.hpp) against its definition, by brute force: every direction ω of the
// side's hemisphere (and of the occluding planes' half-spaces) is seen when the nearest circle (the least
// |ω·n_k|) sees the point ω projects to — read in each plane's own frame from its wedges, sharing nothing
// with the cells, envelopes, frame changes and clipping under test. A cosine-weighted grid integrates that
// labelling; random points check membership away from the cells' boundaries. Random circles (1 to 12;
// repeated, reversed, through the side normal, the horizon's own) and random visible arcs, full turns and
// empty cones included; and the cells' tiling: with every circle wholly visible the pieces cover the
// hemisphere exactly once.
#include "static_core/internal/nearest_circle.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <vector>

#include "static_core/angular_set.hpp"
#include "static_core/cone_assembly.hpp"
#include "static_core/slicing_plan.hpp"
#include "static_core/spherical_polygon.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

constexpr double kPi = kTwoPi / 2;

/// Circles through the vertex: planes through the origin (the assembly reads normal, u and w only).
struct Circles {
  std::vector<SlicingPlane> planes;
  std::vector<std::vector<Wedge>> wedges;
  std::vector<glm::dvec3> half_spaces;
  std::vector<PlanarCone> cones() const {
    std::vector<PlanarCone> out;
    for (std::size_t i = 0; i < planes.size(); ++i) out.push_back({&planes[i], wedges[i]});
    return out;
  }
  /// The definition: whether direction w (unit) is seen.
  bool seen(const glm::dvec3& w, const glm::dvec3& m) const {
    if (glm::dot(w, m) < 0) return false;
    for (const glm::dvec3& h : half_spaces)
      if (glm::dot(w, h) < 0) return false;
    // Every plane of the nearest circle (parallel planes are one circle) reads w's projection in its frame.
    const SlicingPlane* n = nearest(w);
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const SlicingPlane& p = planes[i];
      if (std::abs(std::abs(glm::dot(p.normal, n->normal)) - 1) > 1e-12) continue;
      if (AngularSet::from_wedges(wedges[i]).contains(
              wrap_angle(std::atan2(glm::dot(w, p.w), glm::dot(w, p.u)))))
        return true;
    }
    return false;
  }
  const SlicingPlane* nearest(const glm::dvec3& w) const {
    const SlicingPlane* best = &planes[0];
    for (const SlicingPlane& p : planes)
      if (std::abs(glm::dot(w, p.normal)) < std::abs(glm::dot(w, best->normal))) best = &p;
    return best;
  }
  /// How far w is from deciding otherwise: the least of its margins to every boundary of the definition.
  double margin(const glm::dvec3& w, const glm::dvec3& m) const {
    double least = std::abs(glm::dot(w, m));
    for (const glm::dvec3& h : half_spaces) least = std::min(least, std::abs(glm::dot(w, h)));
    const SlicingPlane* n = nearest(w);
    for (const SlicingPlane& p : planes)
      if (std::abs(std::abs(glm::dot(p.normal, n->normal)) - 1) > 1e-12)
        least = std::min(least, std::abs(glm::dot(w, p.normal)) - std::abs(glm::dot(w, n->normal)));
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const SlicingPlane& p = planes[i];
      if (std::abs(std::abs(glm::dot(p.normal, n->normal)) - 1) > 1e-12) continue;
      const glm::dvec2 q(glm::dot(w, p.u), glm::dot(w, p.w));
      least = std::min(least, glm::length(q));  // near the circle's pole every angle is near
      const double a = std::atan2(q.y, q.x);
      for (const Wedge& e : wedges[i])
        for (const double end : {e.start, e.end()})
          least = std::min(least, std::abs(std::remainder(a - end, kTwoPi)) * glm::length(q));
    }
    return least;
  }
};

/// The labelling's A and cosine-weighted moment, on an n x n grid of equal projected solid angle.
struct Labelled {
  double sky_visibility;
  glm::dvec3 moment;
};
Labelled brute_force(const Circles& c, const glm::dvec3& m, int n) {
  const glm::dvec3 x =
      glm::normalize(glm::cross(m, std::abs(m.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 y = glm::cross(m, x);
  double seen = 0;
  glm::dvec3 moment(0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      // Each ring's azimuths shifted by a golden-ratio fraction of a step: boundaries along meridians
      // (circles through m) do not line up with the grid's columns.
      const double shift = std::fmod(0.6180339887498949 * i, 1.0);
      const double r2 = (i + 0.5) / n, phi = kTwoPi * (j + shift) / n;
      const double r = std::sqrt(r2);
      const glm::dvec3 w = r * std::cos(phi) * x + r * std::sin(phi) * y + std::sqrt(1 - r2) * m;
      if (c.seen(w, m)) {
        seen += 1;
        moment += w;
      }
    }
  return {seen / (double(n) * n), moment};
}

Circles gen_circles(const glm::dvec3& m, bool with_half_spaces) {
  Circles c;
  const int count = *rc::gen::inRange(1, 13);
  for (int k = 0; k < count; ++k) {
    glm::dvec3 n = test::gen_unit_direction();
    switch (*rc::gen::inRange(0, 9)) {
      case 0:  // a circle through the side normal
        if (glm::length(glm::cross(m, n)) > 0.1) n = glm::normalize(glm::cross(m, n));
        break;
      case 1:  // the horizon's circle
        n = m;
        break;
      case 2:  // a repeated circle (its arcs are united with the first's)
        if (k > 0) n = c.planes[0].normal;
        break;
      case 3:  // the first circle, of the opposite normal (another frame: a reflection of its angles)
        if (k > 0) n = -c.planes[0].normal;
        break;
      default:
        break;
    }
    c.planes.push_back(make_plane(n, 0.0, k));
    std::vector<Wedge> w;
    switch (*rc::gen::inRange(0, 6)) {
      case 0:  // nothing seen
        break;
      case 1:
        w.push_back({0.0, kTwoPi});
        break;
      default:
        for (int i = *rc::gen::inRange(1, 4); i > 0; --i)
          w.push_back({*rc::gen::inRange(0, 1 << 16) * (kTwoPi / (1 << 16)),
                       *rc::gen::inRange(1, 1 << 16) * (kPi / (1 << 16))});
    }
    c.wedges.push_back(w);
  }
  if (with_half_spaces)
    for (int i = *rc::gen::inRange(0, 3); i > 0; --i) c.half_spaces.push_back(test::gen_unit_direction());
  return c;
}

ConeMeasures assemble(const Circles& c, const glm::dvec3& m, VisibilityCone& cone) {
  ConeAssemblyScratch scratch;
  ConeMeasures measures;
  assemble_and_measure_cone(c.cones(), m, scratch, cone, &measures, c.half_spaces,
                            ConeReconstruction::NearestCircle);
  return measures;
}

RC_GTEST_PROP(NearestCircle, EqualsTheNearestCircleLabellingOfTheHemisphere, ()) {
  const glm::dvec3 m = test::gen_unit_direction();
  const Circles c = gen_circles(m, *rc::gen::arbitrary<bool>());
  VisibilityCone cone;
  const ConeMeasures measures = assemble(c, m, cone);
  const Labelled truth = brute_force(c, m, 300);
  RC_ASSERT(std::abs(measures.sky_visibility - truth.sky_visibility) < 5e-3);
  // The pieces: in the closed hemisphere, counter-clockwise about m, measured as measure_cone does.
  for (const SphericalPolygon& piece : cone.pieces)
    for (const glm::dvec3& d : piece) RC_ASSERT(glm::dot(d, m) >= -1e-12);
  const ConeMeasures again = measure_cone(cone, m);
  RC_ASSERT(std::abs(again.sky_visibility - measures.sky_visibility) < 1e-12);
  if (truth.sky_visibility > 0.05 && glm::length(truth.moment) > 0)
    RC_ASSERT(glm::dot(measures.bent_normal, glm::normalize(truth.moment)) > std::cos(0.03));
  // Membership, direction by direction, away from the boundaries (which rounding may move).
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 w = test::gen_unit_direction();
    if (c.margin(w, m) < 1e-6) continue;
    bool inside = false;
    for (const SphericalPolygon& piece : cone.pieces) inside = inside || contains_direction(piece, w);
    RC_ASSERT(inside == c.seen(w, m));
  }
}

RC_GTEST_PROP(NearestCircle, WhollyVisibleCirclesTileTheHemisphere, ()) {
  // Every circle wholly visible: the cells cover the hemisphere once, so A = 1 and the solid angle is 2 pi
  // to rounding — the cells neither overlap nor leave gaps.
  const glm::dvec3 m = test::gen_unit_direction();
  Circles c = gen_circles(m, false);
  for (auto& w : c.wedges) w = {{0.0, kTwoPi}};
  VisibilityCone cone;
  ConeMeasures measures = assemble(c, m, cone);
  RC_ASSERT(std::abs(measures.sky_visibility - 1.0) < 1e-9);
  RC_ASSERT(std::abs(measures.solid_angle - kTwoPi) < 1e-9);
  RC_ASSERT(glm::dot(measures.bent_normal, m) > 1 - 1e-9);
  // And nothing seen on any circle: nothing at all.
  for (auto& w : c.wedges) w.clear();
  measures = assemble(c, m, cone);
  RC_ASSERT(cone.pieces.empty());
  RC_ASSERT(measures.sky_visibility == 0.0);
}

RC_GTEST_PROP(NearestCircle, EnvelopesAreTheLeastBoundAtEveryAngle, ()) {
  // The envelope pieces against the least of the bounds computed directly, at random angles.
  NearestCircleAssembler::CircleSet set;
  const int count = *rc::gen::inRange(1, 25);
  for (int k = 0; k < count; ++k) {
    const glm::dvec3 n = test::gen_unit_direction();
    bool repeated = false;
    for (const auto& c : set.circles) repeated = repeated || std::abs(glm::dot(c.n, n)) > 1 - 1e-9;
    if (repeated) continue;
    const SlicingPlane p = make_plane(n, 0.0, k);
    set.circles.push_back({p.normal, p.u, p.w, 1.0});
  }
  NearestCircleAssembler::make_envelopes(set);
  for (std::size_t k = 0; k < set.circles.size(); ++k)
    for (int sheet = 0; sheet < 2; ++sheet) {
      const auto& envelope = set.envelope[2 * k + sheet];
      RC_ASSERT(!envelope.empty());
      for (std::size_t i = 0; i + 1 < envelope.size(); ++i) RC_ASSERT(envelope[i].phi < envelope[i + 1].phi);
      for (int t = 0; t < 50; ++t) {
        const double phi = *rc::gen::inRange(0, 1 << 20) * (kTwoPi / (1 << 20));
        std::size_t i = envelope.size() - 1;
        for (std::size_t j = 0; j < envelope.size(); ++j)
          if (envelope[j].phi <= phi) i = j;
        const glm::dvec3 p = NearestCircleAssembler::envelope_point(set, k, sheet, envelope[i], phi);
        // On the boundary: as near to circle k as to the nearest other circle, and no other nearer.
        const double to_k = std::abs(glm::dot(p, set.circles[k].n));
        double to_others = 1.0;
        for (std::size_t j = 0; j < set.circles.size(); ++j)
          if (j != k) to_others = std::min(to_others, std::abs(glm::dot(p, set.circles[j].n)));
        if (set.circles.size() == 1) {
          RC_ASSERT(to_k > 1 - 1e-12);  // the pole
        } else {
          RC_ASSERT(std::abs(to_k - to_others) < 1e-9);
          RC_ASSERT((sheet == 0 ? 1 : -1) * glm::dot(p, set.circles[k].n) >= -1e-12);
        }
      }
    }
}

TEST(NearestCircle, OneCircleSeenOnAQuarterOfItGivesHalfTheHemisphere) {
  // One circle, of the plane y = 0, about m = +z: its cell is the whole sphere, each direction labelled by
  // its projection onto the circle. Seen on the quarter from +x to +z, the hemisphere is seen where x > 0: A
  // = 1/2 exactly.
  Circles c;
  c.planes.push_back(make_plane({0, 1, 0}, 0.0, 0));
  const glm::dvec3 m(0, 0, 1);
  const SlicingPlane& p = c.planes[0];
  const double at_x = std::atan2(glm::dot(glm::dvec3(1, 0, 0), p.w), glm::dot(glm::dvec3(1, 0, 0), p.u));
  const double at_z = std::atan2(glm::dot(m, p.w), glm::dot(m, p.u));
  const double start = std::abs(wrap_angle(at_z - at_x) - kPi / 2) < 1e-9 ? at_x : at_z;
  c.wedges.push_back({{wrap_angle(start), kPi / 2}});
  VisibilityCone cone;
  const ConeMeasures measures = assemble(c, m, cone);
  EXPECT_NEAR(brute_force(c, m, 400).sky_visibility, 0.5, 1e-3);
  EXPECT_NEAR(measures.sky_visibility, 0.5, 1e-12);
  // With the ground z' = x >= 0 as an occluding plane's side: the same half, nothing cut.
  c.half_spaces = {{1, 0, 0}};
  EXPECT_NEAR(assemble(c, m, cone).sky_visibility, 0.5, 1e-12);
  // And x <= 0: nothing left.
  c.half_spaces = {{-1, 0, 0}};
  EXPECT_NEAR(assemble(c, m, cone).sky_visibility, 0.0, 1e-12);
}

}  // namespace
}  // namespace pleat
