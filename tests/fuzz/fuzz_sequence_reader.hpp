// One harness body for every reader: load the sequence as the CLI does, then read every frame.
#pragma once

#include <filesystem>

#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "support/input_error.hpp"

namespace pleat::fuzz {

inline void load_and_read_all(const std::filesystem::path& input, const std::filesystem::path& cache = {}) {
  try {
    const MeshSequence sequence = load_sequence(input, cache);
    for (std::size_t i = 0; i < sequence.num_frames(); ++i) (void)sequence.frame(i);
  } catch (const InputError&) {
    // The documented answer to bad input.
  }
}

}  // namespace pleat::fuzz
