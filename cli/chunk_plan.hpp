// How a job's frames are cut into chunks and given to ranks. `mpirun -np N pleat visibility|shade ...`
// splits the requested frames into contiguous chunks (one or more per rank), each rank computes its own
// chunks, and rank 0 gathers every frame's result, in frame order, into the one output a single process
// would write, byte for byte (cli/run_chunks.hpp). Render-farm managers split a shot the same way
// (contiguous frame chunks); the kinetic engine needs it (it carries state from frame to frame, so each chunk
// starts with a static build; its output equals the static engine's, so the boundaries cannot show).
//
// Chunks are contiguous and of nearly equal measured cost, and each rank takes a contiguous run of them. The
// cost of a frame is its number of slice vertices (SliceVertexCounter), which the static core's time is
// proportional to (docs/benchmarks.md).
//
// The keys of the checkpoint (cli/checkpoint.hpp), per chunk: the command's output-determining options (the
// slicing plan's bytes among them), the welded topology and vertex map, the frame count, the chunk's range
// and the 64-bit fingerprints of its own frames (taken during the shared loading pass, no extra read). Not
// the job's range or its other chunks: a chunk's bytes do not depend on them, so tasks of other --frames
// sharing the directory use each other's chunks where their bounds meet. A changed frame invalidates its
// chunk (and, through the plan or the bounds, more when it changes those).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/checkpoint.hpp"
#include "cli/shared_load.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::cli {

/// Number of slice vertices of a frame under `plan` (mesh edges crossing each plane): the cost measure of a
/// frame. O(E x orientations x log planes) per frame.
class SliceVertexCounter {
 public:
  SliceVertexCounter(const MeshTopology& topology, const SlicingPlan& plan);
  std::size_t count(const Frame& frame) const;

 private:
  std::vector<glm::dvec3> m_orientations;
  std::vector<std::vector<double>> m_offsets;  // per orientation, sorted (a plan of placed planes)
  double m_spacing = 0.0;                      // > 0: a lattice plan, its planes counted from it
  std::vector<std::pair<Index, Index>> m_edges;
};

/// Boundaries of `chunks` contiguous, non-empty chunks of the frames whose costs are `cost` (frame i of the
/// range costs cost[i]), each of nearly equal total cost: chunk c is [bounds[c], bounds[c+1]) relative to
/// the range start. chunks is clamped to [1, cost.size()].
std::vector<std::size_t> split_by_cost(const std::vector<double>& cost, std::size_t chunks);

/// Owner rank of each chunk: the chunks still to do (todo[c]), in order, cut into `ranks` contiguous runs of
/// nearly equal cost (rank 0 takes the first run); -1 for chunks not to do.
std::vector<int> assign_chunks(const std::vector<double>& chunk_cost, const std::vector<bool>& todo,
                               int ranks);

struct ChunkJob {
  std::size_t first = 0, last = 0;  ///< the requested frames
  std::vector<std::size_t> bounds;  ///< absolute chunk boundaries: chunk c is [bounds[c], bounds[c+1])
  std::vector<int> owner;           ///< rank computing chunk c; -1: read from the checkpoint
  std::optional<Checkpoint> checkpoint;
  std::vector<std::uint64_t> chunk_keys;
  std::size_t kept_chunks = 0;  ///< chunks read from the checkpoint
};

/// Plans the chunks of frames [first, last) for the command: with one rank, no checkpoint and no --chunks,
/// one chunk; else `chunks` chunks (0: one per rank) split by measured cost (SliceVertexCounter over every
/// frame, each rank counting its share), checked against the checkpoint and assigned to ranks. Collective.
/// `options_key` fingerprints the command's output-determining options; `cost_plan` may be null (then every
/// frame costs the same).
ChunkJob plan_chunks(const SharedSequence& input, std::size_t first, std::size_t last, std::size_t chunks,
                     const SlicingPlan* cost_plan, const std::string& checkpoint_dir,
                     std::uint64_t options_key);

}  // namespace pleat::cli
