// What every rank of a job holds alike before the frames are split: the input sequence, loaded with the
// loading pass (validation and welding) shared between the ranks so that no rank reads the whole cache; a
// 64-bit fingerprint of every frame's positions (for the checkpoint, cli/checkpoint.hpp); bounds measured in
// shares and combined; and the slicing plan, made by rank 0 and sent to every rank, so that all ranks slice
// with the same bits. Every function here is collective; with one rank none of them communicates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <utility>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::cli {

/// A sequence loaded by every rank, the loading pass shared between them (LoadScan): rank r validates and
/// welds over the r-th equal share of all frames and fingerprints them; the weld classes are merged with one
/// all-reduce and the frame fingerprints combined, so every rank ends with the same welding and all
/// fingerprints. With one rank: load_sequence, and fingerprints of every frame.
struct SharedSequence {
  MeshSequence sequence;
  std::vector<std::uint64_t> frame_fingerprints;  ///< one per frame of the input
  /// Fingerprint of the welded topology, the map to input vertices and the frame count (the frames have
  /// their own): what every chunk depends on besides its own frames and the plan.
  std::uint64_t welding_fingerprint() const;
};
SharedSequence load_shared(const std::filesystem::path& input, const std::filesystem::path& cache);

/// Frames [first, last) of `ranks` ranks: rank r's equal share by count.
std::pair<std::size_t, std::size_t> share_of(std::size_t first, std::size_t last, int rank, int ranks);

/// Every rank's bounding box lo/hi (3 doubles each) replaced by the box of all of them.
void all_reduce_bounds(double* lo, double* hi);
/// The same elementwise over arrays of float bounds (a rank leaves what it did not measure at +max / lowest).
void all_reduce_bounds(std::vector<float>& lo, std::vector<float>& hi);

/// The plan made by rank 0, sent to every rank (all ranks then slice with the same bits).
/// Its bytes are plan_to_bytes' (static_core/plan_codec.hpp, where its fingerprint is too).
void broadcast_plan(SlicingPlan& plan);

}  // namespace pleat::cli
