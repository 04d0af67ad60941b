#include "cli/memory_limit.hpp"

#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <new>
#include <sstream>

#include "cli/chunk_plan.hpp"
#include "static_core/slicing_plan.hpp"

namespace pleat::cli {

namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kResidentPerSliceVertex = 450;
constexpr std::uint64_t kAddressPerSliceVertex = 500;
constexpr std::uint64_t kAddressPerExtraThread = 64ull << 20;
constexpr std::uint64_t kUnlimited = std::numeric_limits<std::uint64_t>::max();

// The first number of the file, or kUnlimited ("max", missing, unreadable, or above 2^62: what cgroup v1
// writes for no limit).
std::uint64_t read_number(const fs::path& path) {
  std::ifstream in(path);
  std::uint64_t value = 0;
  if (!(in >> value) || value >= (1ull << 62)) return kUnlimited;
  return value;
}

// The value of `key` in a "key value" file (memory.stat), 0 if absent.
std::uint64_t stat_value(const fs::path& path, const std::string& key) {
  std::ifstream in(path);
  std::string name;
  std::uint64_t value = 0;
  while (in >> name >> value)
    if (name == key) return value;
  return 0;
}

// "VmSize" of /proc/self/status, in bytes.
std::uint64_t address_space_used(const fs::path& proc_self) {
  std::ifstream in(proc_self / "status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmSize:", 0) == 0) return std::uint64_t(std::stoull(line.substr(7))) * 1024;
  return 0;
}

// The tightest memory cgroup limit over the process's cgroup and its ancestors: v2 (a "0::/path" line) or v1
// (a line naming the memory controller); what the cgroup holds now, page cache aside.
std::optional<MemoryLimit> cgroup_limit(const fs::path& proc_self, const fs::path& root) {
  std::ifstream in(proc_self / "cgroup");
  std::optional<MemoryLimit> best;
  for (std::string line; std::getline(in, line);) {
    const std::size_t a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string controllers = line.substr(a + 1, b - a - 1);
    const fs::path path = fs::path(line.substr(b + 1)).relative_path();
    const bool v2 = line.compare(0, a, "0") == 0 && controllers.empty();
    const bool v1 = ("," + controllers + ",").find(",memory,") != std::string::npos;
    if (!v1 && !v2) continue;
    for (const fs::path& base :
         v2 ? std::vector<fs::path>{root, root / "unified"} : std::vector<fs::path>{root / "memory"})
      for (fs::path at = path.empty() ? base : base / path;; at = at.parent_path()) {
        const std::uint64_t limit = read_number(at / (v2 ? "memory.max" : "memory.limit_in_bytes"));
        if (limit != kUnlimited && (!best || limit < best->bytes)) {
          const std::uint64_t usage = read_number(at / (v2 ? "memory.current" : "memory.usage_in_bytes"));
          const std::uint64_t cache = stat_value(at / "memory.stat", v2 ? "file" : "total_cache");
          const std::uint64_t used = usage == kUnlimited ? 0 : usage - std::min(usage, cache);
          best = MemoryLimit{
              limit, used, false,
              v2 ? "the memory cgroup's memory.max" : "the memory cgroup's memory.limit_in_bytes"};
        }
        if (at == base || !at.has_relative_path() || at.parent_path() == at) break;
      }
  }
  return best;
}

// The planes that cut `frame` (planes_for_frame: a lattice plan's own planes of the frame).
std::size_t planes_of(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan) {
  std::vector<SlicingPlane> planes;
  planes_for_frame(plan, cloth_vertices(topology), frame, planes);
  return planes.size();
}

// Slice vertices of `frame` under `plan`, or nothing when they cannot be counted (out of memory again).
std::optional<std::size_t> slice_vertices(const MeshTopology& topology, const Frame& frame,
                                          const SlicingPlan& plan) {
  try {
    return SliceVertexCounter(topology, plan).count(frame);
  } catch (const std::bad_alloc&) {
    return std::nullopt;
  }
}

std::string millions(std::size_t n) {
  char text[32];
  if (n >= 1000000)
    std::snprintf(text, sizeof text, "%.1f million", double(n) / 1e6);
  else
    std::snprintf(text, sizeof text, "%zu", n);
  return text;
}

std::string limit_text(const MemoryLimit& limit) {
  return format_bytes(limit.bytes) + " (" + limit.source + ")";
}

}  // namespace

std::optional<MemoryLimit> memory_limit(const fs::path& proc_self, const fs::path& cgroup_root) {
  std::optional<MemoryLimit> best = cgroup_limit(proc_self, cgroup_root);
  struct rlimit address {};
  if (proc_self == "/proc/self" && getrlimit(RLIMIT_AS, &address) == 0 && address.rlim_cur != RLIM_INFINITY &&
      (!best || address.rlim_cur < best->bytes))
    best = MemoryLimit{std::uint64_t(address.rlim_cur), address_space_used(proc_self), true, "ulimit -v"};
  return best;
}

std::uint64_t frame_need(std::size_t slice_vertices, int threads, bool address_space) {
  if (!address_space) return kResidentPerSliceVertex * slice_vertices;
  return kAddressPerSliceVertex * slice_vertices +
         kAddressPerExtraThread * std::uint64_t(std::max(threads - 1, 0));
}

std::string format_bytes(std::uint64_t bytes) {
  char text[32];
  if (bytes >= (1ull << 30))
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / double(1ull << 30));
  else
    std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / double(1ull << 20));
  return text;
}

int run_threads() {
  const std::size_t allowed =
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);  // --threads
  return int(std::min<std::size_t>(allowed, std::size_t(tbb::this_task_arena::max_concurrency())));
}

void check_memory_before_start(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                               std::size_t index, int threads) {
  const std::optional<MemoryLimit> limit = memory_limit();
  if (!limit) return;
  const std::size_t planes = planes_of(topology, frame, plan);  // too many: InputError, as the engine says
  const std::optional<std::size_t> count = slice_vertices(topology, frame, plan);
  if (!count)
    throw OutOfMemory("out of memory before starting, the memory limit being " + limit_text(*limit));
  const std::uint64_t need = frame_need(*count, threads, limit->address_space);
  const std::uint64_t left = limit->bytes - std::min(limit->bytes, limit->used);
  if (need <= left) return;
  std::ostringstream out;
  out << "out of memory before starting: frame " << index << " needs about " << format_bytes(need) << " ("
      << millions(*count) << " slice vertices over " << planes << " planes, " << threads
      << (threads == 1 ? " thread" : " threads") << "), and the memory limit of " << limit_text(*limit)
      << " leaves " << format_bytes(left) << "; raise the limit, or cut with fewer planes (a larger "
      << "--spacing-edges: 0.75 needs about 2/3 as much)";
  throw OutOfMemory(out.str());
}

OutOfMemory out_of_memory_in_frame(const MeshTopology& topology, const Frame& frame, const SlicingPlan& plan,
                                   std::size_t index, int threads) {
  const std::optional<MemoryLimit> limit = memory_limit();
  std::string what = "out of memory computing frame " + std::to_string(index);
  try {
    if (const std::optional<std::size_t> count = slice_vertices(topology, frame, plan))
      what += ", which needs about " +
              format_bytes(frame_need(*count, threads, !limit || limit->address_space)) + " (" +
              millions(*count) + " slice vertices over " + std::to_string(planes_of(topology, frame, plan)) +
              " planes, " + std::to_string(threads) + (threads == 1 ? " thread)" : " threads)");
  } catch (const std::exception&) {  // not even the memory to count them
  }
  if (limit) what += "; the memory limit is " + limit_text(*limit);
  return OutOfMemory(what);
}

std::string out_of_memory_message() {
  const std::optional<MemoryLimit> limit = memory_limit();
  return "out of memory" + (limit ? "; the memory limit is " + limit_text(*limit) : std::string());
}

}  // namespace pleat::cli
