// Plan files: a slicing plan pinned as JSON (`pleat visibility --save-plan FILE`, `--plan FILE`), so that a
// shot split over farm tasks, machines or edits of its cache is cut by the same planes.
//
// A lattice plan (SlicingPlan::spacing > 0) is stored as its orientations, spacing and storage rule; reading
// it gives no planes, and the reader's caller instantiates them over the sequence at hand
// (cover_with_planes: the lattice is anchored in world space, so the planes that cut a frame are the same
// whatever box is covered). Any other plan is stored plane by plane. Doubles are written in the shortest form
// that reads back to the same bits, so a plan round-trips exactly:
//   {"pleat_plan": 1, "storage": "aimed-on-fan", "orientations": [[x, y, z], ...],
//    "spacing": s}                                   (lattice)
//    "planes": [{"orientation": o, "offset": d, "normal": [..], "u": [..], "w": [..]}, ...]
//                                                    (otherwise, instead of "spacing")
#pragma once

#include <filesystem>

#include "static_core/slicing_plan.hpp"

namespace pleat {

/// Writes `plan` atomically (sim_io/atomic_file.hpp). Throws std::runtime_error on I/O failure.
void write_plan_file(const std::filesystem::path& path, const SlicingPlan& plan);

/// Reads a plan file. A lattice plan comes back with spacing > 0 and no planes. Throws InputError naming the
/// file and the place (byte offset of a syntax error, or the key) on anything malformed: not JSON, another
/// version, an unknown storage rule, a non-finite or zero orientation, a spacing that is not positive, a
/// plane of an orientation that does not exist.
SlicingPlan read_plan_file(const std::filesystem::path& path);

}  // namespace pleat
