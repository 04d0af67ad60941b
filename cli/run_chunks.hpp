// The run of a planned job (cli/chunk_plan.hpp): every rank computes its own chunks, one fresh engine per
// chunk, and sends each frame's bytes to rank 0 as soon as it is done; rank 0 computes its chunks, receives
// the others' frames (holding a chunk until it is its turn) and reads the chunks kept by the checkpoint, and
// passes every frame's bytes, in frame order, to the command, which writes the one output a single process
// would. With a checkpoint, every finished chunk is saved by rank 0 as it completes (cli/checkpoint.hpp), so
// a rank lost later does not lose it. Progress per rank and overall on rank 0's stderr.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "cli/checkpoint.hpp"
#include "cli/chunk_plan.hpp"
#include "static_core/visibility.hpp"

namespace pleat::cli {

/// One frame's result as bytes, and where it goes on rank 0.
using EmitFrame = std::function<void(std::size_t frame, std::string bytes)>;
/// Computes frames [first, last) (one chunk: a fresh engine), calling emit once per frame in order.
using ComputeChunk = std::function<void(std::size_t first, std::size_t last, const EmitFrame& emit)>;

/// How far the frame this rank is computing is: the engine's counters (static_core/visibility.hpp; pass
/// `counters` in its params and reset them per frame), the receiving vertices, and the frame (-1: none).
struct FrameWork {
  FrameProgress counters;
  std::size_t vertices = 0;  ///< receiving vertices
  std::atomic<std::int64_t> frame{-1};
};

/// Runs the job: this rank computes its chunks; rank 0 receives every frame's bytes (its own, the other
/// ranks', the checkpoint's) and passes them to `consume` in frame order, keeping finished chunks in the
/// checkpoint. Progress per rank and overall on rank 0's stderr as --progress says (auto: when rank 0's
/// stderr, or mpirun's, is a terminal), with `work` (when given) within rank 0's frames. Collective.
void run_chunks(const ChunkJob& job, const std::string& what, const ComputeChunk& compute,
                const ConsumeFrame& consume, const FrameWork* work = nullptr);

/// Test hook (PLEAT_TEST_KILL_RANK=R): rank R of a job of several ranks raises SIGKILL after emitting its
/// first frame.
void maybe_kill_for_test();

}  // namespace pleat::cli
