// Memory limits that batch systems put on a task, and pleat's estimate of what a frame needs: a run that
// cannot fit says so before it starts, and one that runs out anyway ends with "out of memory" and what it
// needed (exit status 1), not an abort.
//
// The limits: the address-space limit (`ulimit -v`, RLIMIT_AS: SGE's h_vmem), which counts virtual memory,
// and a memory cgroup's (Slurm's, a container's: cgroup v2 memory.max, v1 memory.limit_in_bytes, the lowest
// over the process's cgroup and its ancestors), which counts resident memory.
//
// The need of a frame grows with its slice vertices (mesh edges crossing the planes, cli/chunk_plan.hpp's
// SliceVertexCounter): about 450 bytes resident and 500 bytes of address space each, measured on the
// generated curtain from 30k to 90k vertices and on the bundled sequences (both engines; the kinetic one at
// the high end), plus about 64 MB of address space per thread beyond the first (its malloc arena and stack).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "static_core/mesh.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::cli {

/// The run cannot have the memory it needs: a runtime failure (exit status 1).
class OutOfMemory : public std::runtime_error {
 public:
  explicit OutOfMemory(const std::string& what) : std::runtime_error(what) {}
};

struct MemoryLimit {
  std::uint64_t bytes = 0;  ///< the limit
  std::uint64_t used = 0;  ///< what counts against it now (this process's address space, or the cgroup's use)
  bool address_space = false;  ///< RLIMIT_AS (virtual memory); else a cgroup's (resident memory)
  std::string source;          ///< "ulimit -v" or "the memory cgroup's memory.max", for messages
};

/// The tightest limit on this process, if any: RLIMIT_AS, and the memory cgroup named in `proc_self`/cgroup
/// under `cgroup_root` (the parameters are for tests). Reads a few small files; never throws.
std::optional<MemoryLimit> memory_limit(const std::filesystem::path& proc_self = "/proc/self",
                                        const std::filesystem::path& cgroup_root = "/sys/fs/cgroup");

/// Bytes a frame of `slice_vertices` slice vertices needs with `threads` threads: of address space, or
/// resident.
std::uint64_t frame_need(std::size_t slice_vertices, int threads, bool address_space);

/// "3.2 GB", "850 MB".
std::string format_bytes(std::uint64_t bytes);

/// Before any work: throws OutOfMemory when a memory limit is known and `frame` (number `index`, the first
/// to compute: the cloth in its scene, as the engine slices it) under `plan` needs more than the limit
/// leaves, saying how much, why (slice vertices, planes, threads) and what to do. Cost: one slice-vertex
/// count of the frame (SliceVertexCounter), and only under a limit.
void check_memory_before_start(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                               std::size_t index, int threads);

/// The OutOfMemory to throw when computing frame number `index` ran out of memory (std::bad_alloc): what it
/// needs by the estimate (when the slice vertices can be counted) and the limit (when one is known).
OutOfMemory out_of_memory_in_frame(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                                   std::size_t index, int threads);

/// "out of memory" with the limit, when one is known: the message of any other std::bad_alloc.
std::string out_of_memory_message();

/// The threads a run uses (--threads, or all cores), for the estimates.
int run_threads();

}  // namespace pleat::cli
