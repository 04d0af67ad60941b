// Brute-force 2D visibility: the oracle for static_core's funnel-tree cones.
//
// For a slice vertex X and a side, the cone is the set of directions, inside the side's angular range at X
// (between the chain edges at X), along which the ray from X meets no slice edge except at X itself. The
// range and the blocked spans are found by an exact angular sweep over every slice edge (orientation
// predicates of CGAL; angles only to represent the result). No triangulation, no regions, no trees.
// Cost: O(n log n) per vertex, O(n^2 log n) per slice.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "static_core/angular_set.hpp"
#include "static_core/internal/slice_cones.hpp"
#include "static_core/mesh_slicer.hpp"

namespace pleat::oracle {

/// cones[x][side] for every slice vertex x.
std::vector<std::array<AngularSet, 2>> brute_force_slice_cones(const Slice& slice);

/// The total angle where two sets differ.
double angular_difference(const AngularSet& a, const AngularSet& b);

/// The first slice vertex and side of `slice` whose cone in `cones` (what `who` computed) differs from
/// `expected` by more than 1e-9 rad, described; "" when none does.
std::string first_mismatch(const Slice& slice, const SliceCones& cones,
                           const std::vector<std::array<AngularSet, 2>>& expected, const std::string& who);

}  // namespace pleat::oracle
