// The one check of a cloth handed to an engine: every entry that takes (topology, frame) calls these before
// it reads a position, so a wrong frame is an error that names the problem, never an out-of-bounds read.
//
// What is checked: the topology's triangle indices are below num_vertices (once per engine object, or per
// one-shot call: a topology is fixed for a sequence); a frame has exactly num_vertices positions, all
// coordinates finite (every frame). Failures throw ArgumentError(who, place, what) (an InputError,
// support/input_error.hpp: a bad call), `who` being the entry (e.g. "compute_visibility"), `place` the
// frame (by its time) and vertex, or the triangle; a position beyond +-2^53 throws a plain InputError (a
// frame far out is bad input, which readers refuse before it reaches an engine: sim_io/mesh_sequence.hpp).
// Cost: one pass over the indices (a max reduction) and one over the positions (a branch-free sum), no
// allocation unless the input is invalid (strings are built only to report a failure).
// Thread safety: pure functions.
#pragma once

#include <string>

#include "static_core/mesh.hpp"

namespace pleat {

/// Throws InputError(who, "triangle T", "vertex index V out of range (N vertices)") for the first
/// triangle that names a vertex >= topology.num_vertices.
void validate_topology(const MeshTopology& topology, const char* who);

/// Throws InputError(who, "frame at t=T", "too few|too many positions: P for N vertices") if the frame's
/// position count is not topology.num_vertices, and InputError(who, "frame at t=T, vertex V", ...) for the
/// first vertex with a NaN or infinite coordinate, or one beyond +-2^53 (where doubles stop holding every
/// integer, and so every plane offset and crossing a slice needs).
void validate_frame(const MeshTopology& topology, const Frame& frame, const char* who);

/// "frame at t=T": how errors name a frame.
std::string frame_place(const Frame& frame);

/// Both, topology first: for one-shot entries.
void validate_mesh(const MeshTopology& topology, const Frame& frame, const char* who);

}  // namespace pleat
