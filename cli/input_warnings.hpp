// What the subcommands that compute cones (visibility, shade, compare) say about the cloth before they start:
// one warning line each on stderr, never a failure, about what makes part of the output meaningless.
#pragma once

#include <cstddef>

#include "sim_io/mesh_sequence.hpp"

namespace pleat::cli {

/// Warns of: the input vertices no triangle uses (no surface, so no visibility: the CSV leaves their fields
/// empty), naming the first few; the degenerate triangles of `frame` (collinear corners: no area, they block
/// nothing; `pleat info` counts every frame's); the self-intersections of `frame` (the algorithm assumes
/// none; `pleat info --check-intersections` lists every frame's). Call on one rank. Cost: one frame's
/// self-intersection test, O(F log F).
void warn_about_cloth(const MeshSequence& sequence, std::size_t frame);

}  // namespace pleat::cli
