// Plan files: a slicing plan pinned as JSON (`pleat visibility --save-plan FILE`, `--plan FILE`), so that a
// shot split over farm tasks, machines or edits of its cache is cut by the same planes.
//
// The file holds the plan's JSON (static_core/plan_codec.hpp: the format, and an exact round trip).
#pragma once

#include <filesystem>

#include "static_core/slicing_plan.hpp"

namespace pleat {

/// Writes `plan` atomically (support/atomic_file.hpp). Throws std::runtime_error on I/O failure.
void write_plan_file(const std::filesystem::path& path, const SlicingPlan& plan);

/// Reads a plan file (plan_from_json). Throws InputError naming the file for one it cannot open, and as
/// plan_from_json on anything malformed.
SlicingPlan read_plan_file(const std::filesystem::path& path);

}  // namespace pleat
