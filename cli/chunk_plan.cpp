#include "cli/chunk_plan.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <glm/geometric.hpp>
#include <span>

#include "cli/job_error.hpp"
#include "cli/world.hpp"
#include "support/fingerprint.hpp"

namespace pleat::cli {

SliceVertexCounter::SliceVertexCounter(const MeshTopology& topology, const SlicingPlan& plan)
    : m_orientations(plan.orientations), m_offsets(plan.orientations.size()), m_spacing(plan.spacing) {
  // Planes per orientation as sorted offsets along its normal; an edge crosses the planes whose offsets lie
  // between its endpoints' heights (a vertex on a plane counts as above it, as the slicer perturbs it).
  for (const SlicingPlane& p : plan.planes) m_offsets[std::size_t(p.orientation)].push_back(p.offset);
  for (auto& o : m_offsets) std::sort(o.begin(), o.end());
  m_edges.reserve(3 * topology.triangles.size());
  for (const Triangle& t : topology.triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      m_edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(m_edges.begin(), m_edges.end());
  m_edges.erase(std::unique(m_edges.begin(), m_edges.end()), m_edges.end());
}

std::size_t SliceVertexCounter::count(const Frame& frame) const {
  std::size_t count = 0;
  std::vector<double> height(frame.positions.size());
  for (std::size_t o = 0; o < m_offsets.size(); ++o) {
    const std::vector<double>& offsets = m_offsets[o];
    if (offsets.empty() && !(m_spacing > 0)) continue;
    for (std::size_t v = 0; v < height.size(); ++v)
      height[v] = glm::dot(m_orientations[o], frame.positions[v]);
    for (const auto& [a, b] : m_edges) {
      const auto [lo, hi] = std::minmax(height[a], height[b]);
      if (m_spacing > 0)  // the lattice planes (k + 1/2) * spacing in (lo, hi]
        count +=
            std::size_t(std::min(std::floor(hi / m_spacing - 0.5) - std::floor(lo / m_spacing - 0.5), 1e15));
      else
        count += std::size_t(std::upper_bound(offsets.begin(), offsets.end(), hi) -
                             std::upper_bound(offsets.begin(), offsets.end(), lo));
    }
  }
  return count;
}

std::vector<std::size_t> split_by_cost(const std::vector<double>& cost, std::size_t chunks) {
  const std::size_t n = cost.size();
  chunks = std::clamp<std::size_t>(chunks, 1, std::max<std::size_t>(n, 1));
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + std::max(cost[i], 0.0);
  if (!(prefix[n] > 0.0))  // nothing measured: by count
    for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = double(i + 1);
  std::vector<std::size_t> bounds{0};
  for (std::size_t c = 1; c < chunks; ++c) {
    const double target = prefix[n] * double(c) / double(chunks);
    // The boundary whose prefix is nearest the target, leaving at least one frame per chunk on each side.
    std::size_t b = std::size_t(std::lower_bound(prefix.begin(), prefix.end(), target) - prefix.begin());
    if (b > 0 && target - prefix[b - 1] < prefix[b] - target) --b;
    b = std::clamp(b, bounds.back() + 1, n - (chunks - c));
    bounds.push_back(b);
  }
  bounds.push_back(n);
  return bounds;
}

std::vector<int> assign_chunks(const std::vector<double>& chunk_cost, const std::vector<bool>& todo,
                               int ranks) {
  std::vector<std::size_t> work;
  for (std::size_t c = 0; c < todo.size(); ++c)
    if (todo[c]) work.push_back(c);
  std::vector<int> owner(todo.size(), -1);
  std::vector<double> cost;
  for (std::size_t c : work) cost.push_back(chunk_cost[c]);
  const std::vector<std::size_t> runs = split_by_cost(cost, std::size_t(ranks));
  for (std::size_t r = 0; r + 1 < runs.size(); ++r)
    for (std::size_t k = runs[r]; k < runs[r + 1]; ++k) owner[work[k]] = int(r);
  return owner;
}

ChunkJob plan_chunks(const SharedSequence& input, std::size_t first, std::size_t last, std::size_t chunks,
                     const SlicingPlan* cost_plan, const std::string& checkpoint_dir,
                     std::uint64_t options_key) {
  ChunkJob job;
  job.first = first, job.last = last;
  const std::size_t n = last - first;
  std::vector<double> cost(n, 1.0);
  if (!World::distributed() && checkpoint_dir.empty() && chunks <= 1) {  // one chunk
    job.bounds = {first, last};
    job.owner = {0};
    return job;
  }
  if (chunks == 0) chunks = std::size_t(World::size());
  if (cost_plan && chunks > 1) {
    // Each rank measures its share of the frames; the sum over ranks gives every rank the same costs.
    std::exception_ptr error;
    const auto [a, b] = share_of(first, last, World::rank(), World::size());
    std::fill(cost.begin(), cost.end(), 0.0);
    try {
      const SliceVertexCounter counter(input.sequence.topology(), *cost_plan);
      for (std::size_t f = a; f < b; ++f) cost[f - first] = double(counter.count(input.sequence.frame(f)));
    } catch (...) {
      error = std::current_exception();
    }
    agree(error);
    World::all_reduce(std::span(cost), World::Reduction::Sum);
  }
  std::vector<std::size_t> bounds = split_by_cost(cost, chunks);
  for (std::size_t& b : bounds) b += first;
  job.bounds = bounds;
  const std::size_t count = bounds.size() - 1;
  std::vector<double> chunk_cost(count, 0.0);
  for (std::size_t c = 0; c < count; ++c)
    for (std::size_t f = bounds[c]; f < bounds[c + 1]; ++f) chunk_cost[c] += cost[f - first];

  // A chunk's bytes depend on its own frames, the options and the welding, not on the rest of the job (the
  // kinetic engine starts each chunk with a static build, which gives the static engine's bytes).
  Fingerprint common;
  common.add_value(options_key).add_value(input.welding_fingerprint());
  for (std::size_t c = 0; c < count; ++c) {
    Fingerprint key;
    key.add_value(common.value()).add_value(bounds[c]).add_value(bounds[c + 1]);
    for (std::size_t f = bounds[c]; f < bounds[c + 1]; ++f) key.add_value(input.frame_fingerprints[f]);
    job.chunk_keys.push_back(key.value());
  }
  std::vector<bool> todo(count, true);
  if (!checkpoint_dir.empty()) {
    job.checkpoint.emplace(checkpoint_dir);
    std::string kept(count, '\0');  // rank 0 scans the directory and tells the others
    std::exception_ptr error;
    if (World::root()) try {
        const std::vector<bool> found = job.checkpoint->scan(bounds, job.chunk_keys);
        for (std::size_t c = 0; c < count; ++c) kept[c] = found[c] ? 1 : 0;
      } catch (...) {
        error = std::current_exception();
      }
    agree(error);
    World::broadcast(kept, 0);
    for (std::size_t c = 0; c < count; ++c) {
      todo[c] = kept[c] == 0;
      job.kept_chunks += kept[c] != 0;
    }
  }
  job.owner = assign_chunks(chunk_cost, todo, World::size());
  return job;
}

}  // namespace pleat::cli
