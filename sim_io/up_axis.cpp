#include "sim_io/up_axis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <stdexcept>

namespace pleat {

void AxisTurn::bounds(glm::vec3& lo, glm::vec3& hi) const {
  const glm::vec3 a = lo, b = hi;
  for (int k = 0; k < 3; ++k) {
    lo[k] = sign[k] > 0 ? a[from[k]] : -b[from[k]];
    hi[k] = sign[k] > 0 ? b[from[k]] : -a[from[k]];
  }
}

AxisTurn turn_to_y_up(int axis, int sign) {
  AxisTurn t;
  if (axis == 1 && sign > 0) return t;
  if (axis == 1) return {{0, 1, 2}, {1, -1, -1}};                     // half a turn about x
  if (axis == 2) return {{0, 2, 1}, {1, float(sign), -float(sign)}};  // a quarter turn about x
  return {{1, 0, 2}, {-float(sign), float(sign), 1}};                 // a quarter turn about z
}

namespace {

glm::dvec3 centroid(const Frame& frame) {
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& p : frame.positions) sum += p;
  return sum / double(std::max<std::size_t>(1, frame.positions.size()));
}

std::string axis_name(int axis, int sign) { return std::string(sign > 0 ? "+" : "-") + char('x' + axis); }

/// The axis and sign of a unit vector along an axis; {-1, 0} otherwise.
std::array<int, 2> as_axis(const glm::dvec3& v) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(v[k]) == 1.0 && v[(k + 1) % 3] == 0.0 && v[(k + 2) % 3] == 0.0)
      return {k, v[k] > 0 ? 1 : -1};
  return {-1, 0};
}

}  // namespace

std::array<int, 2> fall_direction(const MeshSequence& cloth) {
  if (cloth.num_frames() < 2) return {-1, 0};
  const Frame first = cloth.frame(0), last = cloth.frame(cloth.num_frames() - 1);
  glm::dvec3 lo(first.positions.front()), hi(lo);
  for (const glm::dvec3& p : first.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::dvec3 moved = centroid(last) - centroid(first);
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(moved[k]) > std::abs(moved[axis])) axis = k;
  const double along = std::abs(moved[axis]);
  const bool clear = along >= 0.05 * glm::length(hi - lo) && along >= 2.0 * std::abs(moved[(axis + 1) % 3]) &&
                     along >= 2.0 * std::abs(moved[(axis + 2) % 3]);
  return clear ? std::array<int, 2>{axis, moved[axis] < 0 ? 1 : -1} : std::array<int, 2>{-1, 0};
}

UpChoice choose_up(std::string_view text, std::string_view ground, const MeshSequence& cloth) {
  std::array<int, 2> from_ground{-1, 0};
  if (!ground.empty()) {
    const GroundPlane plane = parse_ground_plane(ground);  // up: its open side
    from_ground = {plane.axis, plane.up > 0 ? 1 : -1};
  }
  const std::array<int, 2> fall = fall_direction(cloth);
  UpChoice choice;
  std::array<int, 2> axis{-1, 0};
  const std::string given(text);
  if (given == "auto") {
    if (from_ground[0] >= 0)
      axis = from_ground, choice.source = "--ground " + std::string(ground);
    else
      axis = {1, 1}, choice.source = "the default";
  } else if (given.size() <= 2 && !given.empty() && given.back() >= 'x' && given.back() <= 'z' &&
             (given.size() == 1 || given[0] == '-' || given[0] == '+')) {
    axis = {given.back() - 'x', given[0] == '-' ? -1 : 1};
    choice.source = "--up";
  } else {
    glm::dvec3 v;
    char tail = 0;
    if (std::sscanf(given.c_str(), "%lf,%lf,%lf%c", &v.x, &v.y, &v.z, &tail) != 3 || !(glm::length(v) > 0.0))
      throw std::invalid_argument("--up: expected auto, x, y, z, -x, -y, -z or X,Y,Z, got '" + given + "'");
    choice.up = glm::normalize(v);
    choice.name = given;
    choice.source = "--up";
    axis = as_axis(choice.up);
  }
  if (axis[0] >= 0) {
    choice.up = glm::dvec3(0.0);
    choice.up[axis[0]] = axis[1];
    choice.turn = turn_to_y_up(axis[0], axis[1]);
    choice.name = axis_name(axis[0], axis[1]);
  }
  {
    const auto disagrees = [&](std::array<int, 2> evidence) {
      return evidence[0] >= 0 && glm::dot(choice.up, glm::dvec3(evidence[0] == 0 ? evidence[1] : 0,
                                                                evidence[0] == 1 ? evidence[1] : 0,
                                                                evidence[0] == 2 ? evidence[1] : 0)) < 0.5;
    };
    const std::string told = given == "auto" ? "up " + choice.name + " (the default)" : "--up " + given;
    if (disagrees(from_ground))
      choice.warning = told + ", but the cloth stands on --ground " + std::string(ground) + " (up " +
                       axis_name(from_ground[0], from_ground[1]) + ")";
    else if (disagrees(fall))
      choice.warning = told + ", but the cloth falls along " + axis_name(fall[0], -fall[1]) + ": if " +
                       axis_name(fall[0], fall[1]) + " is up, give --up " + (fall[1] > 0 ? "" : "-") +
                       std::string(1, char('x' + fall[0])) + " or --ground";
  }
  return choice;
}

}  // namespace pleat
