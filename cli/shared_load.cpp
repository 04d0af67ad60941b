#include "cli/shared_load.hpp"

#include <cstring>
#include <exception>
#include <map>
#include <optional>
#include <span>
#include <unordered_map>

#include "cli/job_error.hpp"
#include "cli/world.hpp"
#include "sim_io/load_sequence.hpp"
#include "static_core/plan_codec.hpp"
#include "support/fingerprint.hpp"

namespace pleat::cli {

namespace {

// Canonical weld classes: labels renumbered by first appearance in input order.
void canonical(std::uint32_t* labels, std::size_t n) {
  std::unordered_map<std::uint32_t, std::uint32_t> renumber;
  renumber.reserve(n);
  for (std::size_t v = 0; v < n; ++v)
    labels[v] = renumber.try_emplace(labels[v], std::uint32_t(renumber.size())).first->second;
}

// The meet of two partitions in canonical labels (vertices stay together only where both keep them
// together), in canonical labels again: associative and commutative.
void meet_partitions(const std::byte* in, std::byte* inout, std::size_t size) {
  const std::size_t n = size / sizeof(std::uint32_t);
  std::vector<std::uint32_t> a(n), b(n);
  std::memcpy(a.data(), in, size);
  std::memcpy(b.data(), inout, size);
  std::unordered_map<std::uint64_t, std::uint32_t> classes;
  classes.reserve(n);
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint64_t key = (std::uint64_t(a[v]) << 32) | b[v];
    b[v] = classes.try_emplace(key, std::uint32_t(classes.size())).first->second;
  }
  std::memcpy(inout, b.data(), size);
}

}  // namespace

std::uint64_t SharedSequence::welding_fingerprint() const {
  Fingerprint f;
  const MeshTopology& topology = sequence.topology();
  f.add_value(topology.num_vertices).add_value(sequence.num_frames());
  f.add(topology.triangles.data(), topology.triangles.size() * sizeof(Triangle));
  f.add(sequence.welded_of_input().data(), sequence.welded_of_input().size() * sizeof(Index));
  return f.value();
}

std::pair<std::size_t, std::size_t> share_of(std::size_t first, std::size_t last, int rank, int ranks) {
  const std::size_t n = last - first;
  return {first + n * std::size_t(rank) / std::size_t(ranks),
          first + n * std::size_t(rank + 1) / std::size_t(ranks)};
}

SharedSequence load_shared(const std::filesystem::path& input, const std::filesystem::path& cache) {
  std::map<std::size_t, std::uint64_t> mine;  // fingerprints of the frames this rank read
  LoadOptions options;
  options.scan.on_frame = [&](std::size_t i, const std::vector<glm::dvec3>& positions) {
    mine[i] = Fingerprint().add(positions.data(), positions.size() * sizeof(glm::dvec3)).value();
  };
  if (World::distributed()) {
    options.scan.range = [](std::size_t num_frames) {
      return share_of(0, num_frames, World::rank(), World::size());
    };
    options.scan.merge_bounds = [](Bounds& bounds) { all_reduce_bounds(&bounds.lo.x, &bounds.hi.x); };
    options.scan.merge = [](std::vector<Index>& classes, std::exception_ptr error) {
      agree(error);  // the lowest bad frame, as one process would report it
      static_assert(sizeof(Index) == sizeof(std::uint32_t));
      canonical(reinterpret_cast<std::uint32_t*>(classes.data()), classes.size());
      World::all_reduce(std::as_writable_bytes(std::span(classes)), meet_partitions);
    };
  }
  std::optional<MeshSequence> sequence;
  std::exception_ptr error;
  try {
    sequence.emplace(load_sequence(input, cache, options));
  } catch (const JobError&) {
    throw;  // agreed inside the scan
  } catch (...) {
    error = std::current_exception();  // before the scan (mesh, header): met by every rank, or by this one
  }
  agree(error);  // pairs with the agree() inside merge on ranks that reached it
  SharedSequence shared{std::move(*sequence), {}};
  shared.frame_fingerprints.assign(shared.sequence.num_frames(), 0);
  for (const auto& [i, hash] : mine) shared.frame_fingerprints[i] = hash;
  // Each frame was fingerprinted by one rank alone, the others hold 0 there.
  World::all_reduce(std::span(shared.frame_fingerprints), World::Reduction::BitXor);
  return shared;
}

void all_reduce_bounds(double* lo, double* hi) {
  World::all_reduce(std::span(lo, 3), World::Reduction::Min);
  World::all_reduce(std::span(hi, 3), World::Reduction::Max);
}

void all_reduce_bounds(std::vector<float>& lo, std::vector<float>& hi) {
  World::all_reduce(std::span(lo), World::Reduction::Min);
  World::all_reduce(std::span(hi), World::Reduction::Max);
}

void broadcast_plan(SlicingPlan& plan) {
  if (!World::distributed()) return;
  std::string bytes;
  if (World::root()) bytes = plan_to_bytes(plan);
  World::broadcast(bytes, 0);
  plan = plan_from_bytes(bytes);
}

}  // namespace pleat::cli
