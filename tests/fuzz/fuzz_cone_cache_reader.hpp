// The body of fuzz_cone_cache, shared with the regression test (tests/fuzz_regressions_test.cpp): read a cone
// cache as `pleat shade --cones` does, for the 9-vertex grid of fuzz_support.hpp (the seeds are caches of
// that grid, so the frames' fingerprints match): the header, the mesh check and every frame block. InputError
// is the documented answer to bad input; anything else propagates (a finding).
#pragma once

#include <filesystem>

#include "fuzz/fuzz_support.hpp"
#include "shading/cone_cache.hpp"
#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "support/input_error.hpp"

namespace pleat::fuzz {

inline void read_cone_cache_for_grid(const std::filesystem::path& path) {
  static const MeshSequence grid = load_sequence(grid_obj());
  static const Frame frame = grid.frame(0);
  try {
    ConeCacheReader reader(path);
    reader.check_mesh(grid.topology(), grid.welded_of_input());
    FrameVisibility cones;
    for (std::size_t k = 0; k < reader.header().frames.size(); ++k) reader.read_frame(k, frame, cones);
  } catch (const InputError&) {
    // The documented answer to bad input.
  }
}

}  // namespace pleat::fuzz
