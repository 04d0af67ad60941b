// The frame-coherence benchmark's coherence cases: what a frame costs the kinetic engine against the static
// one when only part of the cloth moves (docs/method.md §11.6; bench/run_frame_coherence.sh runs it).
//
// On each real sequence in the scene it was simulated in (bench/coherence/sequences.hpp), from its last frame
// (the cloth settled):
//   still      the frame held: every frame the same positions, bit for bit;
//   corner     the cloth at rest while one corner is lifted: the 5% of its vertices nearest (along edges) to
//              the cloth vertex farthest from its centre rise a little more each frame, tapering to nothing
//              at the rim of that region;
//   patch1, patch10, patch50  a patch of 1%, 10% or 50% of the vertices (nearest along edges to the vertex
//              nearest the cloth's centre) waving, tapering to nothing at its rim, the rest bit-identical;
// and the sequence itself at the native frame rate (u1) and 4x and 8x (u4, u8: frames interpolated in
// between, a vertex at rest staying bit for bit where it is). The static and kinetic engines are built on
// frame 0 (untimed), then frames 1.. are computed by each in turn at one thread (no TBB parallelism) and each
// frame's process CPU time is taken; kinetic ÷ static is the median of the per-frame ratios (and the ratio of
// the medians is given too). The two engines' A values must be equal bit for bit on every frame (else exit
// 1). Outputs: DIR/frame_coherence_cases.csv and DIR/frame_coherence_cases.md (bench/plot_coherence_cases.py
// draws DIR/frame_coherence_cases.png from the CSV).
//
// Flags: --out DIR (default bench/results), --sequences a,b (default: every real sequence in data/),
// --frames N (timed frames per case, default 12), --cases a,b (default all), --data DIR, --quick (the drape,
// 3 frames, every case).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "bench/bench_args.hpp"
#include "bench/coherence/sequences.hpp"
#include "bench/coherence/stopwatch.hpp"
#include "kinetic/kinetic_visibility.hpp"
#include "static_core/mesh_connectivity.hpp"
#include "static_core/visibility.hpp"

namespace pleat::bench {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kCases = {"still", "corner", "patch1", "patch10", "patch50", "u1", "u4", "u8"};

struct CaseRow {
  std::string name, sequence;
  Index vertices = 0;
  double moved = 0;                      ///< median fraction of the cloth's vertices that moved per frame
  double static_ms = 0, kinetic_ms = 0;  ///< medians per frame
  double ratio = 0;                      ///< median of kinetic ÷ static per frame
  double kept = 0, assembled = 0;        ///< per frame: slices kept whole, vertices assembled again (shares)
  double structure_ms = 0, cones_ms = 0, assembly_ms = 0;  ///< the kinetic frame's parts (wall, means)
  bool equal = true;
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// The first `count` cloth vertices met walking the edges from `seed`, with their depth.
std::vector<std::pair<Index, int>> ball(const MeshConnectivity& connectivity, Index seed, std::size_t count) {
  std::vector<int> depth(connectivity.num_vertices(), -1);
  std::vector<std::pair<Index, int>> out;
  std::deque<Index> queue{seed};
  depth[seed] = 0;
  while (!queue.empty() && out.size() < count) {
    const Index v = queue.front();
    queue.pop_front();
    out.emplace_back(v, depth[v]);
    for (const Index u : connectivity.neighbours(v))
      if (depth[u] < 0) depth[u] = depth[v] + 1, queue.push_back(u);
  }
  return out;
}

double mean_edge(const MeshConnectivity& connectivity, const Frame& frame) {
  double sum = 0;
  for (const auto& e : connectivity.endpoints())
    sum += glm::distance(frame.positions[e[0]], frame.positions[e[1]]);
  return connectivity.endpoints().empty() ? 1.0 : sum / double(connectivity.endpoints().size());
}

/// The frames of case `name` on sequence `s` (frame 0 untimed, then `count`).
std::vector<Frame> case_frames(const Sequence& s, const std::string& name, int count) {
  if (name[0] == 'u') return make_frames(s, std::stod(name.substr(1)), count + 1);
  const Frame base = s.native(s.native_available - 1);
  std::vector<Frame> frames(std::size_t(count) + 1, base);
  for (std::size_t f = 0; f < frames.size(); ++f) frames[f].time = base.time + double(f) / 24.0;
  if (name == "still") return frames;
  const MeshConnectivity cloth(s.cloth);
  const Index n = s.cloth.num_vertices;
  glm::dvec3 centre(0.0);
  for (Index v = 0; v < n; ++v) centre += base.positions[v] / double(n);
  auto by_distance = [&](bool farthest) {
    Index best = 0;
    for (Index v = 1; v < n; ++v) {
      const double d = glm::distance(base.positions[v], centre),
                   b = glm::distance(base.positions[best], centre);
      if (farthest ? d > b : d < b) best = v;
    }
    return best;
  };
  const double edge = mean_edge(cloth, cloth_part(s, base));
  const bool corner = name == "corner";
  const double share = corner ? 0.05 : std::stod(name.substr(5)) / 100.0;
  const auto region = ball(cloth, by_distance(corner), std::max<std::size_t>(1, std::size_t(share * n)));
  int rim = 1;
  for (const auto& [v, d] : region) rim = std::max(rim, d + 1);
  for (std::size_t f = 1; f < frames.size(); ++f)
    for (const auto& [v, d] : region) {
      const double w = 1.0 - double(d) / double(rim);  // 1 at the seed, 0 past the rim
      const glm::dvec3 p = base.positions[v];
      const double phase = 0.5 * double(f);
      frames[f].positions[v] += corner ? glm::dvec3(0.0, 0.3 * edge * double(f) * w * w, 0.0)
                                       : 0.3 * edge * w *
                                             glm::dvec3(std::sin(3.1 * p.y / edge * 0.1 + phase),
                                                        std::cos(2.3 * p.x / edge * 0.1 + phase),
                                                        std::sin(2.7 * p.z / edge * 0.1 + 1.7 * phase));
    }
  return frames;
}

bool same_sky(const FrameVisibility& a, const FrameVisibility& b) {
  for (int side = 0; side < 2; ++side) {
    if (a.measures[side].size() != b.measures[side].size()) return false;
    for (std::size_t v = 0; v < a.measures[side].size(); ++v)
      if (std::bit_cast<std::uint64_t>(a.measures[side][v].sky_visibility) !=
          std::bit_cast<std::uint64_t>(b.measures[side][v].sky_visibility))
        return false;
  }
  return true;
}

CaseRow run_case(const Sequence& s, const std::string& name, int count) {
  const std::vector<Frame> frames = case_frames(s, name, count);
  const SlicingPlan plan = default_plan(s, frames[0]);
  StaticVisibility fixed(s.topology, plan, {false});
  KineticParams serial;
  serial.parallel = false;
  KineticVisibility kinetic(s.topology, plan, frames[0], serial);
  fixed.compute(frames[0]);
  CaseRow row{name, s.name, s.cloth.num_vertices};
  std::vector<double> st, kt, ratio, moved;
  const Index n = s.cloth.num_vertices;
  for (std::size_t f = 1; f < frames.size(); ++f) {
    const Stopwatch a;
    const FrameVisibility& sv = fixed.compute(frames[f]);
    st.push_back(a.process_cpu_ms());
    const Stopwatch b;
    const FrameVisibility& kv = kinetic.advance(frames[f]);
    kt.push_back(b.process_cpu_ms());
    ratio.push_back(kt.back() / st.back());
    row.equal = row.equal && same_sky(sv, kv);
    std::size_t m = 0;
    for (Index v = 0; v < n; ++v)
      m += std::memcmp(&frames[f].positions[v], &frames[f - 1].positions[v], sizeof(glm::dvec3)) != 0;
    moved.push_back(double(m) / double(n));
    const KineticFrameStats& k = kinetic.last_stats();
    row.kept += double(k.slices_kept) / double(std::max<std::size_t>(sv.stats.slices, 1)) / double(count);
    row.assembled += double(k.vertices_assembled) / double(n) / double(count);
    row.structure_ms += 1e3 * k.structure_seconds / double(count);
    row.cones_ms += 1e3 * k.cone_seconds / double(count);
    row.assembly_ms += 1e3 * k.assembly_seconds / double(count);
  }
  row.moved = median(moved);
  row.static_ms = median(st);
  row.kinetic_ms = median(kt);
  row.ratio = median(ratio);
  return row;
}

void write(const std::vector<CaseRow>& rows, const fs::path& out, int count) {
  fs::create_directories(out);
  std::ofstream csv(out / "frame_coherence_cases.csv");
  csv << "case,sequence,vertices,moved_fraction,static_ms,kinetic_ms,ratio,ratio_of_medians,slices_kept,"
         "vertices_assembled,kinetic_structure_ms,kinetic_cones_ms,kinetic_assembly_ms,equal\n";
  for (const CaseRow& r : rows)
    csv << format("%s,%s,%u,%.6f,%.3f,%.3f,%.4f,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%d\n", r.name.c_str(),
                  r.sequence.c_str(), r.vertices, r.moved, r.static_ms, r.kinetic_ms, r.ratio,
                  r.kinetic_ms / r.static_ms, r.kept, r.assembled, r.structure_ms, r.cones_ms, r.assembly_ms,
                  int(r.equal));
  std::ofstream md(out / "frame_coherence_cases.md");
  md << "Coherence cases (bench/coherence_cases_bench.cpp): " << count
     << " timed frames per case, one thread, process CPU time per frame; kinetic ÷ static = median of the "
        "per-frame ratios. moved: median share of the cloth's vertices whose position changed; kept: share "
        "of "
        "the slices kept whole; assembled: share of the vertices whose 3D cones were assembled again; where "
        "the kinetic frame goes: carrying the reached slices' structure, growing their 2D cones, the 3D "
        "assembly (shares of their sum, from the engine's wall-time counters).\n\n"
        "| case | sequence | vertices | moved | static ms | kinetic ms | kinetic ÷ static | kept | assembled "
        "| "
        "structure / cones / assembly | equal |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const CaseRow& r : rows) {
    const double parts = std::max(r.structure_ms + r.cones_ms + r.assembly_ms, 1e-12);
    md << format(
        "| %s | %s | %u | %.4f | %.1f | %.2f | **%.4f** | %.2f | %.3f | %.0f%% / %.0f%% / %.0f%% | %s |\n",
        r.name.c_str(), r.sequence.c_str(), r.vertices, r.moved, r.static_ms, r.kinetic_ms, r.ratio, r.kept,
        r.assembled, 100 * r.structure_ms / parts, 100 * r.cones_ms / parts, 100 * r.assembly_ms / parts,
        r.equal ? "yes" : "NO");
  }
}

int run(int argc, char** argv) {
  fs::path out = "bench/results", data = fs::path(PLEAT_BENCH_SOURCE_DIR) / "data";
  std::vector<std::string> sequences, cases = kCases;
  int count = 12;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out")
      out = next_value(argc, argv, i);
    else if (arg == "--data")
      data = next_value(argc, argv, i);
    else if (arg == "--sequences")
      sequences = split(next_value(argc, argv, i));
    else if (arg == "--cases")
      cases = split(next_value(argc, argv, i));
    else if (arg == "--frames")
      count = std::stoi(next_value(argc, argv, i));
    else if (arg == "--quick")
      sequences = {"drape"}, count = 3;
    else
      throw std::invalid_argument("unknown flag " + arg);
  }
  if (count < 1) throw std::invalid_argument("--frames must be at least 1");
  for (const std::string& c : cases)
    if (std::find(kCases.begin(), kCases.end(), c) == kCases.end())
      throw std::invalid_argument("no case " + c);
  if (sequences.empty())
    for (const std::string& name : default_sequences(data))
      if (is_real_sequence(name, data)) sequences.push_back(name);
  std::vector<CaseRow> rows;
  bool all_equal = true;
  for (const std::string& name : sequences) {
    if (!is_real_sequence(name, data))
      throw std::invalid_argument(name + " is not a real sequence in " + data.string());
    const Sequence s = make_sequence(name, 0, data, true);
    for (const std::string& c : cases) {
      rows.push_back(run_case(s, c, count));
      const CaseRow& r = rows.back();
      all_equal = all_equal && r.equal;
      std::fprintf(stderr,
                   "[coherence_cases] %s %s: moved %.4f, static %.1f ms, kinetic %.2f ms, ratio %.3f%s\n",
                   name.c_str(), c.c_str(), r.moved, r.static_ms, r.kinetic_ms, r.ratio,
                   r.equal ? "" : " (NOT EQUAL)");
    }
  }
  write(rows, out, count);
  std::printf("coherence_cases: wrote %s\n", (out / "frame_coherence_cases.csv").string().c_str());
  if (!all_equal) std::printf("coherence_cases: FAILED: kinetic and static differ\n");
  return all_equal ? 0 : 1;
}

}  // namespace
}  // namespace pleat::bench

int main(int argc, char** argv) {
  return pleat::bench::run_main("coherence_cases_bench", pleat::bench::run, argc, argv);
}
