// The cloth sequences of the frame-coherence benchmark and their frames at a temporal resolution.
//
// Real sequences: every data/NAME/ holding NAME.obj + NAME.pc2 (Blender simulations: drape, pile, rucked,
// ...), their size fixed, taken from a start sample where the cloth has landed (the drape from sample 20; the
// others from 24 samples before their end, so that the most folded frames are measured). Generated sequences:
// ClothGenerator's kinds (curtain, roll, flag, sleeve) at resolution sqrt(size) (3025 -> 55, 29929 -> 173,
// 300304 -> 548), 48 frames per motion cycle (24 fps), from frame 8 on (the cycle loops, so any length is
// available). Temporal resolution u: 1 = native frames; u = 2, 4, 8 insert u-1 linearly interpolated frames
// between consecutive native frames; u = 0.5 takes every other native frame. Frame k is at native time k / u.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "static_core/mesh.hpp"

namespace pleat::bench {

struct Sequence {
  std::string name;
  Index size = 0;  ///< as asked for (0 for a real sequence)
  bool real = false;
  MeshTopology topology;
  std::function<Frame(std::size_t)> native;  ///< native frame i, counted from the start frame
  std::size_t native_available = 0;          ///< SIZE_MAX: loops
};

/// The real sequences found in `data` (sorted, the drape first), then the generated kinds.
std::vector<std::string> default_sequences(const std::filesystem::path& data);
bool is_sequence_name(const std::string& name, const std::filesystem::path& data);
bool is_real_sequence(const std::string& name, const std::filesystem::path& data);

/// Throws std::invalid_argument for a size that is not a square grid, and the readers' errors.
Sequence make_sequence(const std::string& name, Index size, const std::filesystem::path& data);

/// Frames 0..count-1 at temporal resolution u. Throws std::out_of_range past the sequence's end.
std::vector<Frame> make_frames(const Sequence& s, double u, int count);

}  // namespace pleat::bench
