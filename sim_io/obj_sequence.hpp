// Numbered OBJ sequences: one OBJ file per frame, all with the same connectivity (same vertex count and the
// same faces), positions changing. Named either by a printf pattern ("frames/f_%04d.obj": every number
// present in the pattern's directory, in numeric order) or by a directory (its .obj files in name order, runs
// of digits compared as numbers so f_2 comes before f_10; two or more must be one sequence: the same name
// around the last run of digits, distinct numbers). Either way the numbers advance by one regular step (1, or
// N for every Nth frame exported): a gap is refused, naming the missing file.
//
// Frame i's source frame number is the last run of digits in its file's name (frame_0012.obj: 12); it sits at
// time number / scene_fps. Opening reads the first file (for the connectivity, and the triangles its
// positions give its polygons); read_frame(i) parses file i and checks its polygons against the first's, so a
// long sequence streams.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sim_io/mesh_sequence.hpp"

namespace pleat {

/// True when `input` looks like a printf pattern with one integer conversion (%d, %0Nd, %Nd, %i).
bool is_frame_pattern(const std::string& input);

/// The frame files of a printf pattern, in numeric order. Throws InputError(pattern) when the pattern is
/// malformed, when no file matches, or naming the first missing file of a gap (numbers not advancing by
/// one regular step).
std::vector<std::filesystem::path> expand_frame_pattern(const std::string& pattern);

/// The .obj files of a directory in natural name order. Throws InputError(directory) when there are none,
/// when two or more are not one numbered sequence (a name without a number, another name around it, a number
/// twice), and InputError naming the first missing file of a gap.
std::vector<std::filesystem::path> list_obj_directory(const std::filesystem::path& directory);

/// Loads (and welds) the sequence of OBJ files. Throws InputError naming the file that differs in
/// connectivity from the first, or holds bad data.
MeshSequence load_obj_sequence(const std::string& name, const std::vector<std::filesystem::path>& files,
                               double scene_fps = kDefaultSceneFps, const LoadScan& scan = {});

/// Writes one OBJ per frame of `sequence` (welded vertices) named by the printf `pattern` with numbers
/// first_number, first_number + 1, ...; each file atomically.
void write_obj_sequence(const std::string& pattern, const MeshSequence& sequence, int first_number = 0);

}  // namespace pleat
