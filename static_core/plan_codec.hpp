// The slicing plan's one codec (docs/method.md §12): its bytes (sent from one rank to the others), its JSON
// (a plan file, sim_io/plan_file.hpp) and its fingerprint (a checkpoint's key, cli/checkpoint.hpp), each
// over every field of SlicingPlan and SlicingPlane, the rules by their names in the tables
// (static_core/cone_rules.hpp) in the JSON and by their ids in the bytes and the fingerprint.
//
// JSON: a lattice plan (spacing > 0) is its orientations, spacing and rules, read back without planes (the
// caller instantiates the planes that cut each frame: planes_for_frame); any other plan is stored plane by
// plane. Doubles are written in the shortest form that reads back to the same bits:
//   {"orientations": [[x, y, z], ...], "pleat_plan": 1, "reconstruction": "grouped",
//    "spacing": s,                                   (lattice)
//    "planes": [{"normal": [..], "offset": d, "orientation": o, "u": [..], "w": [..]}, ...],  (otherwise)
//    "storage": "aimed-on-fan"}
// A file without "reconstruction" (written before it was saved) holds a grouped plan.
// Cost: O(orientations + planes). Thread safety: none needed (pure functions).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "static_core/slicing_plan.hpp"

namespace pleat {

/// Every field, in the host's byte order and layout (for another process of the same build).
std::string plan_to_bytes(const SlicingPlan& plan);
/// The plan of plan_to_bytes' bytes, bit for bit. Throws std::runtime_error for truncated bytes and
/// std::invalid_argument for a rule id of no row.
SlicingPlan plan_from_bytes(std::string_view bytes);

/// The plan file's text (with a final newline).
std::string plan_to_json(const SlicingPlan& plan);
/// The plan of a plan file's text; a lattice comes back with spacing > 0 and no planes. Throws InputError
/// naming `file` and the place (byte offset of a syntax error, or the key) on anything malformed: not JSON,
/// another version, an unknown rule, a non-finite or zero orientation, a spacing that is not positive, a
/// plane of an orientation that does not exist.
SlicingPlan plan_from_json(std::string_view text, const std::string& file);

/// A 64-bit fingerprint of every field (the reconstruction added only when not grouped, so that the keys of
/// grouped plans stay those of the files that did not know it).
std::uint64_t plan_fingerprint(const SlicingPlan& plan);

}  // namespace pleat
