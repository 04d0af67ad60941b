#include "cli/distributed.hpp"

// The C API only (Open MPI's deprecated C++ bindings would need libmpi_cxx).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <glm/geometric.hpp>
#include <iostream>
#include <map>
#include <numeric>
#include <unordered_map>

#include "cli/global_options.hpp"
#include "cli/progress.hpp"
#include "sim_io/atomic_file.hpp"
#include "sim_io/load_sequence.hpp"

namespace pleat::cli {

namespace {

bool g_mpi = false;
std::chrono::steady_clock::time_point g_start = std::chrono::steady_clock::now();
int g_rank = 0;
int g_size = 1;

constexpr int kFrameTag = 1;     // one frame's result: header (chunk, frame) + payload
constexpr int kProgressTag = 2;  // a rank's count of frames done

constexpr char kChunkMagic[8] = {'P', 'L', 'E', 'A', 'T', 'C', 'K', '1'};
constexpr char kChunkEnd[8] = {'P', 'L', 'E', 'A', 'T', 'E', 'N', 'D'};

void check(int status, const char* what) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

// Sends of this rank still in flight (their buffers must live until they complete).
struct PendingSends {
  std::deque<std::pair<MPI_Request, std::string>> sends;
  void send(std::string bytes, int tag) {
    sends.emplace_back(MPI_REQUEST_NULL, std::move(bytes));
    auto& [request, buffer] = sends.back();
    check(MPI_Isend(buffer.data(), int(buffer.size()), MPI_BYTE, 0, tag, MPI_COMM_WORLD, &request), "Isend");
    reap();
  }
  void reap() {  // frees the buffers of completed sends at the front
    while (!sends.empty()) {
      int done = 0;
      check(MPI_Test(&sends.front().first, &done, MPI_STATUS_IGNORE), "Test");
      if (!done) return;
      sends.pop_front();
    }
  }
  void wait_all() {
    for (auto& [request, buffer] : sends) check(MPI_Wait(&request, MPI_STATUS_IGNORE), "Wait");
    sends.clear();
  }
};

// Canonical weld classes: labels renumbered by first appearance in input order.
void canonical(std::uint32_t* labels, std::size_t n) {
  std::unordered_map<std::uint32_t, std::uint32_t> renumber;
  renumber.reserve(n);
  for (std::size_t v = 0; v < n; ++v)
    labels[v] = renumber.try_emplace(labels[v], std::uint32_t(renumber.size())).first->second;
}

// MPI_Op: the meet of two partitions (vertices stay together only where both keep them together).
std::size_t g_meet_length = 0;
extern "C" void meet_partitions(void* in, void* inout, int* count, MPI_Datatype*) {
  const auto* a = static_cast<const std::uint32_t*>(in);
  auto* b = static_cast<std::uint32_t*>(inout);
  for (int k = 0; k < *count; ++k, a += g_meet_length, b += g_meet_length) {
    std::unordered_map<std::uint64_t, std::uint32_t> classes;
    classes.reserve(g_meet_length);
    for (std::size_t v = 0; v < g_meet_length; ++v) {
      const std::uint64_t key = (std::uint64_t(a[v]) << 32) | b[v];
      b[v] = classes.try_emplace(key, std::uint32_t(classes.size())).first->second;
    }
  }
}

std::string chunk_name(std::size_t first, std::size_t last) {
  char name[96];
  std::snprintf(name, sizeof name, "chunk_%08zu_%08zu.pleatchunk", first, last);
  return name;
}

struct ChunkHeader {
  char magic[8];
  std::uint64_t job_key, chunk_key, first, last;
};

// Whether this rank's stderr is a terminal, or under mpirun its launcher's: for --progress auto.
bool launcher_terminal() {
  if (isatty(STDERR_FILENO) != 0) return true;
  if (!g_mpi) return false;
  // Under mpirun a rank's stderr is a pipe to its launcher (mpirun itself on its node): show progress when
  // the launcher's stderr is a terminal.
  char target[256] = {};
  const std::string link = "/proc/" + std::to_string(getppid()) + "/fd/2";
  const ssize_t n = ::readlink(link.c_str(), target, sizeof target - 1);
  const std::string tty(target, n > 0 ? std::size_t(n) : 0);
  return tty.rfind("/dev/pts/", 0) == 0 || tty.rfind("/dev/tty", 0) == 0;
}

}  // namespace

// ---- World ----

void World::init(int& argc, char**& argv) {
  g_start = std::chrono::steady_clock::now();
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMIX_RANK")) return;
  int provided = 0;
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "Init");
  g_mpi = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
}

void World::finalize() {
  if (g_mpi) MPI_Finalize();
  g_mpi = false;
}

int World::rank() { return g_rank; }
double World::seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count();
}
int World::size() { return g_size; }

void World::abort(int code) {
  remove_uncommitted_files();
  if (g_mpi) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

void agree(std::exception_ptr error) {
  if (g_size == 1) {
    if (error) std::rethrow_exception(error);
    return;
  }
  int mine = error ? g_rank : g_size, lowest = g_size;
  check(MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "Allreduce");
  if (lowest == g_size) return;
  std::string message;
  int code = 1;
  if (g_rank == lowest) {
    try {
      std::rethrow_exception(error);
    } catch (const JobError& e) {
      message = e.what(), code = e.code();
    } catch (const std::exception& e) {
      message = e.what(), code = exit_status_of(e);
    } catch (...) {
      message = "unknown error";
    }
  }
  auto length = std::uint64_t(message.size());
  check(MPI_Bcast(&length, 1, MPI_UINT64_T, lowest, MPI_COMM_WORLD), "Bcast");
  message.resize(length);
  check(MPI_Bcast(message.data(), int(length), MPI_CHAR, lowest, MPI_COMM_WORLD), "Bcast");
  check(MPI_Bcast(&code, 1, MPI_INT, lowest, MPI_COMM_WORLD), "Bcast");
  throw JobError(message, code);
}

// ---- Fingerprints and loading ----

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
  if (g_size > 1) {
    options.scan.range = [](std::size_t num_frames) { return share_of(0, num_frames, g_rank, g_size); };
    options.scan.merge_bounds = [](Bounds& bounds) { all_reduce_bounds(&bounds.lo.x, &bounds.hi.x); };
    options.scan.merge = [](std::vector<Index>& classes, std::exception_ptr error) {
      agree(error);  // the lowest bad frame, as one process would report it
      static_assert(sizeof(Index) == sizeof(std::uint32_t));
      canonical(reinterpret_cast<std::uint32_t*>(classes.data()), classes.size());
      MPI_Datatype vector_type;
      check(MPI_Type_contiguous(int(classes.size()), MPI_UINT32_T, &vector_type), "Type_contiguous");
      MPI_Type_commit(&vector_type);
      MPI_Op op;
      MPI_Op_create(&meet_partitions, 1, &op);
      g_meet_length = classes.size();
      std::vector<Index> merged(classes.size());
      check(MPI_Allreduce(classes.data(), merged.data(), 1, vector_type, op, MPI_COMM_WORLD), "Allreduce");
      MPI_Op_free(&op);
      MPI_Type_free(&vector_type);
      classes = std::move(merged);
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
  if (g_size > 1)
    check(MPI_Allreduce(MPI_IN_PLACE, shared.frame_fingerprints.data(), int(shared.frame_fingerprints.size()),
                        MPI_UINT64_T, MPI_BXOR, MPI_COMM_WORLD),
          "Allreduce");
  return shared;
}

void all_reduce_bounds(double* lo, double* hi) {
  if (g_size == 1) return;
  check(MPI_Allreduce(MPI_IN_PLACE, lo, 3, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD), "Allreduce");
  check(MPI_Allreduce(MPI_IN_PLACE, hi, 3, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "Allreduce");
}

void all_reduce_bounds(std::vector<float>& lo, std::vector<float>& hi) {
  if (g_size == 1) return;
  check(MPI_Allreduce(MPI_IN_PLACE, lo.data(), int(lo.size()), MPI_FLOAT, MPI_MIN, MPI_COMM_WORLD),
        "Allreduce");
  check(MPI_Allreduce(MPI_IN_PLACE, hi.data(), int(hi.size()), MPI_FLOAT, MPI_MAX, MPI_COMM_WORLD),
        "Allreduce");
}

void broadcast_plan(SlicingPlan& plan) {
  if (g_size == 1) return;
  auto counts =
      std::array<std::uint64_t, 3>{plan.orientations.size(), plan.planes.size(), std::uint64_t(plan.storage)};
  check(MPI_Bcast(counts.data(), 3, MPI_UINT64_T, 0, MPI_COMM_WORLD), "Bcast");
  check(MPI_Bcast(&plan.spacing, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD), "Bcast");
  plan.orientations.resize(counts[0]);
  plan.planes.resize(counts[1]);
  plan.storage = ConeStorage(counts[2]);
  check(MPI_Bcast(plan.orientations.data(), int(counts[0] * sizeof(glm::dvec3)), MPI_BYTE, 0, MPI_COMM_WORLD),
        "Bcast");
  check(MPI_Bcast(plan.planes.data(), int(counts[1] * sizeof(SlicingPlane)), MPI_BYTE, 0, MPI_COMM_WORLD),
        "Bcast");
}

std::uint64_t plan_fingerprint(const SlicingPlan& plan) {
  Fingerprint f;
  f.add_value(int(plan.storage)).add_value(plan.spacing);
  f.add(plan.orientations.data(), plan.orientations.size() * sizeof(glm::dvec3));
  for (const SlicingPlane& p : plan.planes)
    f.add_value(p.normal).add_value(p.offset).add_value(p.u).add_value(p.w).add_value(p.orientation);
  return f.value();
}

// ---- Cost and chunks ----

SliceVertexCounter::SliceVertexCounter(const MeshTopology& topology, const SlicingPlan& plan)
    : m_orientations(plan.orientations), m_offsets(plan.orientations.size()) {
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
    if (offsets.empty()) continue;
    for (std::size_t v = 0; v < height.size(); ++v)
      height[v] = glm::dot(m_orientations[o], frame.positions[v]);
    for (const auto& [a, b] : m_edges) {
      const auto [lo, hi] = std::minmax(height[a], height[b]);
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

// ---- Checkpoint ----

Checkpoint::Checkpoint(std::filesystem::path dir, std::uint64_t job_key)
    : m_dir(std::move(dir)), m_job_key(job_key) {}

std::filesystem::path Checkpoint::path_of(std::size_t first, std::size_t last) const {
  return m_dir / chunk_name(first, last);
}

std::vector<bool> Checkpoint::scan(const std::vector<std::size_t>& bounds,
                                   const std::vector<std::uint64_t>& chunk_keys) {
  std::filesystem::create_directories(m_dir);
  std::map<std::string, std::size_t> wanted;
  for (std::size_t c = 0; c + 1 < bounds.size(); ++c) wanted[chunk_name(bounds[c], bounds[c + 1])] = c;
  std::vector<bool> kept(bounds.size() - 1, false);
  std::size_t stale = 0;
  for (const auto& entry : std::filesystem::directory_iterator(m_dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".pleatchunk" || name.rfind("chunk_", 0) != 0) continue;
    ChunkHeader header{};
    char end[8] = {};
    std::ifstream in(entry.path(), std::ios::binary);
    in.read(reinterpret_cast<char*>(&header), sizeof header);
    const auto size = entry.file_size();
    if (in && size >= sizeof header + sizeof end) {
      in.seekg(std::streamoff(size - sizeof end));
      in.read(end, sizeof end);
    }
    const auto it = wanted.find(name);
    const bool valid = in && std::equal(kChunkMagic, kChunkMagic + 8, header.magic) &&
                       std::equal(kChunkEnd, kChunkEnd + 8, end) && header.job_key == m_job_key &&
                       it != wanted.end() && header.chunk_key == chunk_keys[it->second];
    if (valid) {
      kept[it->second] = true;
    } else {
      std::filesystem::remove(entry.path());
      ++stale;
    }
  }
  if (stale > 0)
    std::cerr << "pleat: checkpoint " << m_dir.string() << ": " << stale
              << " chunk file(s) of another input, plan or command removed (their key differs)\n";
  return kept;
}

ChunkJob plan_chunks(const SharedSequence& input, std::size_t first, std::size_t last, std::size_t chunks,
                     const SlicingPlan* cost_plan, const std::string& checkpoint_dir,
                     std::uint64_t options_key) {
  ChunkJob job;
  job.first = first, job.last = last;
  const std::size_t n = last - first;
  std::vector<double> cost(n, 1.0);
  if (g_size == 1 && checkpoint_dir.empty() && chunks <= 1) {  // as before MPI: one chunk
    job.bounds = {first, last};
    job.owner = {0};
    return job;
  }
  if (chunks == 0) chunks = std::size_t(g_size);
  if (cost_plan && chunks > 1) {
    // Each rank measures its share of the frames; the sum over ranks gives every rank the same costs.
    std::exception_ptr error;
    const auto [a, b] = share_of(first, last, g_rank, g_size);
    std::fill(cost.begin(), cost.end(), 0.0);
    try {
      const SliceVertexCounter counter(input.sequence.topology(), *cost_plan);
      for (std::size_t f = a; f < b; ++f) cost[f - first] = double(counter.count(input.sequence.frame(f)));
    } catch (...) {
      error = std::current_exception();
    }
    agree(error);
    if (g_size > 1)
      check(MPI_Allreduce(MPI_IN_PLACE, cost.data(), int(n), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD),
            "Allreduce");
  }
  std::vector<std::size_t> bounds = split_by_cost(cost, chunks);
  for (std::size_t& b : bounds) b += first;
  job.bounds = bounds;
  const std::size_t count = bounds.size() - 1;
  std::vector<double> chunk_cost(count, 0.0);
  for (std::size_t c = 0; c < count; ++c)
    for (std::size_t f = bounds[c]; f < bounds[c + 1]; ++f) chunk_cost[c] += cost[f - first];

  Fingerprint job_key;
  job_key.add_value(options_key).add_value(input.welding_fingerprint()).add_value(first).add_value(last);
  job_key.add(bounds.data(), bounds.size() * sizeof(std::size_t));
  for (std::size_t c = 0; c < count; ++c) {
    Fingerprint key;
    key.add_value(job_key.value()).add_value(bounds[c]).add_value(bounds[c + 1]);
    for (std::size_t f = bounds[c]; f < bounds[c + 1]; ++f) key.add_value(input.frame_fingerprints[f]);
    job.chunk_keys.push_back(key.value());
  }
  std::vector<bool> todo(count, true);
  if (!checkpoint_dir.empty()) {
    job.checkpoint.emplace(checkpoint_dir, job_key.value());
    std::vector<char> kept(count, 0);
    std::exception_ptr error;
    if (g_rank == 0) try {
        const std::vector<bool> found = job.checkpoint->scan(bounds, job.chunk_keys);
        for (std::size_t c = 0; c < count; ++c) kept[c] = found[c];
      } catch (...) {
        error = std::current_exception();
      }
    agree(error);
    if (g_size > 1) check(MPI_Bcast(kept.data(), int(count), MPI_CHAR, 0, MPI_COMM_WORLD), "Bcast");
    for (std::size_t c = 0; c < count; ++c) {
      todo[c] = !kept[c];
      job.kept_chunks += kept[c] != 0;
    }
  }
  job.owner = assign_chunks(chunk_cost, todo, g_size);
  return job;
}

// ---- Running ----

void maybe_kill_for_test() {
  static const char* target = std::getenv("PLEAT_TEST_KILL_RANK");
  if (target && std::atoi(target) == g_rank && g_size > 1) std::raise(SIGKILL);
}

namespace {

// Rank 0's view of the progress: frames done per rank, shown as one bar or line (cli/progress.hpp) with the
// counts of each rank.
class RankProgress {
 public:
  // Collective: rank 0 decides whether progress is shown, and every rank learns it (the other ranks then
  // send rank 0 one message per frame, which it receives to the last).
  RankProgress(std::string what, const ChunkJob& job) : m_total(g_size, 0), m_done(g_size, 0) {
    const ProgressMode mode = g_rank == 0 ? progress_mode(launcher_terminal()) : ProgressMode::None;
    int enabled = mode != ProgressMode::None ? 1 : 0;
    if (g_size > 1) check(MPI_Bcast(&enabled, 1, MPI_INT, 0, MPI_COMM_WORLD), "Bcast");
    m_enabled = enabled != 0;
    for (std::size_t c = 0; c + 1 < job.bounds.size(); ++c)
      if (job.owner[c] >= 0) m_total[std::size_t(job.owner[c])] += job.bounds[c + 1] - job.bounds[c];
    m_line.emplace(std::move(what), std::accumulate(m_total.begin(), m_total.end(), std::size_t(0)), "frames",
                   mode);
  }
  bool enabled() const { return m_enabled; }
  void set(int rank, std::size_t done) {
    m_done[std::size_t(rank)] = done;
    print();
  }
  void drain(bool wait = false) {  // progress messages of the other ranks; with `wait`, all of them
    if (!m_enabled || g_size == 1) return;
    for (int r = 1; r < g_size; ++r) {
      while (m_done[std::size_t(r)] < m_total[std::size_t(r)]) {
        int flag = 1;
        if (!wait) check(MPI_Iprobe(r, kProgressTag, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE), "Iprobe");
        if (!flag) break;
        std::uint64_t done = 0;
        check(MPI_Recv(&done, 1, MPI_UINT64_T, r, kProgressTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "Recv");
        m_done[std::size_t(r)] = done;
      }
    }
    print();
  }
  void finish() { m_line->finish(); }

 private:
  void print() {
    if (!m_enabled) return;
    std::string ranks;
    if (g_size > 1)
      for (int r = 0; r < g_size; ++r)
        ranks += "  r" + std::to_string(r) + " " + std::to_string(m_done[std::size_t(r)]) + "/" +
                 std::to_string(m_total[std::size_t(r)]);
    m_line->set(std::accumulate(m_done.begin(), m_done.end(), std::size_t(0)), ranks);
  }
  bool m_enabled;
  std::vector<std::size_t> m_total, m_done;
  std::optional<Progress> m_line;
};

// Writes one chunk file: header, frame records, end marker.
class ChunkFile {
 public:
  ChunkFile(const Checkpoint& checkpoint, std::size_t first, std::size_t last, std::uint64_t chunk_key)
      : m_file(checkpoint.path_of(first, last)) {
    ChunkHeader header{};
    std::copy(kChunkMagic, kChunkMagic + 8, header.magic);
    header.job_key = checkpoint.job_key(), header.chunk_key = chunk_key, header.first = first,
    header.last = last;
    m_file.stream().write(reinterpret_cast<const char*>(&header), sizeof header);
  }
  void add(std::size_t frame, std::string_view bytes) {
    const std::uint64_t record[2] = {frame, bytes.size()};
    m_file.stream().write(reinterpret_cast<const char*>(record), sizeof record);
    m_file.stream().write(bytes.data(), std::streamsize(bytes.size()));
  }
  void commit() {
    m_file.stream().write(kChunkEnd, sizeof kChunkEnd);
    m_file.commit();
  }

 private:
  AtomicFile m_file;
};

void read_chunk_file(const std::filesystem::path& path, const ConsumeFrame& consume) {
  std::ifstream in(path, std::ios::binary);
  ChunkHeader header{};
  in.read(reinterpret_cast<char*>(&header), sizeof header);
  for (std::size_t f = header.first; f < header.last && in; ++f) {
    std::uint64_t record[2] = {};
    in.read(reinterpret_cast<char*>(record), sizeof record);
    std::string bytes(record[1], '\0');
    in.read(bytes.data(), std::streamsize(bytes.size()));
    if (!in || record[0] != f) break;
    consume(f, bytes);
  }
  if (!in) throw std::runtime_error(path.string() + ": checkpoint chunk unreadable");
}

}  // namespace

void run_chunks(const ChunkJob& job, const std::string& what, const ComputeChunk& compute,
                const ConsumeFrame& consume) {
  const std::size_t count = job.bounds.size() - 1;
  RankProgress progress(what, job);
  if (g_rank != 0) {
    // Compute this rank's chunks; every frame goes to rank 0 as soon as it is done (header: chunk, frame).
    PendingSends pending;
    std::uint64_t done = 0;
    for (std::size_t c = 0; c < count; ++c) {
      if (job.owner[c] != g_rank) continue;
      compute(job.bounds[c], job.bounds[c + 1], [&](std::size_t frame, std::string bytes) {
        ByteWriter message;
        message.put<std::uint64_t>(c).put<std::uint64_t>(frame);
        std::string buffer = message.take();
        buffer += bytes;
        pending.send(std::move(buffer), kFrameTag);
        ++done;
        if (progress.enabled())
          pending.send(std::string(reinterpret_cast<const char*>(&done), sizeof done), kProgressTag);
        maybe_kill_for_test();
      });
    }
    pending.wait_all();
    return;
  }

  // Rank 0: frames of other ranks arrive in order per rank; hold each chunk until it is its turn. With a
  // checkpoint, finished chunks of other ranks are saved as they arrive (drained between rank 0's own
  // frames), so that a rank lost later does not lose them; without one, they wait in their senders' memory.
  std::map<std::size_t, std::vector<std::pair<std::size_t, std::string>>> received;
  auto receive_one = [&](bool wait) {
    MPI_Status status;
    int flag = 1;
    if (wait)
      check(MPI_Probe(MPI_ANY_SOURCE, kFrameTag, MPI_COMM_WORLD, &status), "Probe");
    else
      check(MPI_Iprobe(MPI_ANY_SOURCE, kFrameTag, MPI_COMM_WORLD, &flag, &status), "Iprobe");
    if (!flag) return false;
    int size = 0;
    MPI_Get_count(&status, MPI_BYTE, &size);
    std::string buffer(std::size_t(size), '\0');
    check(MPI_Recv(buffer.data(), size, MPI_BYTE, status.MPI_SOURCE, kFrameTag, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE),
          "Recv");
    ByteReader header(buffer);
    const auto c = header.get<std::uint64_t>();
    const auto frame = header.get<std::uint64_t>();
    auto& frames = received[c];
    frames.emplace_back(frame, buffer.substr(2 * sizeof(std::uint64_t)));
    if (job.checkpoint && frames.size() == job.bounds[c + 1] - job.bounds[c]) {
      ChunkFile file(*job.checkpoint, job.bounds[c], job.bounds[c + 1], job.chunk_keys[c]);
      for (const auto& [f, bytes] : frames) file.add(f, bytes);
      file.commit();
      frames.clear();
      frames.shrink_to_fit();
      received.erase(c);
    }
    return true;
  };

  std::size_t own_done = 0;
  for (std::size_t c = 0; c < count; ++c) {
    const std::size_t first = job.bounds[c], last = job.bounds[c + 1];
    if (job.owner[c] == 0) {
      std::optional<ChunkFile> file;
      if (job.checkpoint) file.emplace(*job.checkpoint, first, last, job.chunk_keys[c]);
      compute(first, last, [&](std::size_t frame, std::string bytes) {
        if (file) file->add(frame, bytes);
        consume(frame, bytes);
        progress.set(0, ++own_done);
        progress.drain();
        if (job.checkpoint && g_size > 1)
          while (receive_one(false)) {
          }
      });
      if (file) file->commit();
    } else if (job.owner[c] < 0 || job.checkpoint) {
      // Kept from an earlier run, or saved as it arrived: wait for it if it has not come in yet.
      if (job.owner[c] > 0)
        while (!std::filesystem::exists(job.checkpoint->path_of(first, last))) {
          receive_one(true);
          progress.drain();
        }
      read_chunk_file(job.checkpoint->path_of(first, last), consume);
    } else {
      auto& frames = received[c];
      while (frames.size() < last - first) {
        receive_one(true);
        progress.drain();
      }
      for (const auto& [f, bytes] : frames) consume(f, bytes);
      received.erase(c);
    }
  }
  progress.drain(/*wait=*/true);
  progress.finish();
}

}  // namespace pleat::cli
