// Scale-out over MPI ranks (issue 16): `mpirun -np N pleat visibility|shade ...` splits the requested frames
// into contiguous chunks (one or more per rank), each rank streams and computes its own chunks, and rank 0
// gathers every frame's result, in frame order, into the one output a single process would write, byte for
// byte. Render-farm managers split a shot the same way (contiguous frame chunks); the kinetic engine needs it
// (it carries state from frame to frame, so each chunk starts with a static build; its output equals the
// static engine's, so the boundaries cannot show).
//
// What lives here, one idea each:
//  - World: MPI initialised only when launched by mpirun (Open MPI's OMPI_COMM_WORLD_SIZE or PMIx's PMIX_RANK
//    in the environment); otherwise a world of one rank that never calls MPI: without mpirun nothing changes.
//  - JobError and agree(): errors every rank learns about (bad input), reported once by rank 0. An error only
//    one rank meets (or a rank killed) aborts the whole job (MPI_Abort / Open MPI's own kill); rank 0 then
//    removes its temporary output files from its termination handler (cli/termination.hpp), so no partial
//    output is left.
//  - load_shared(): the loading pass (validation and welding) split between the ranks, so no rank reads the
//    whole cache, and a 64-bit fingerprint of every frame's positions for the checkpoint.
//  - split_by_cost() / assign_chunks(): contiguous chunks of nearly equal measured cost, and contiguous runs
//  of
//    them per rank. The cost of a frame is its number of slice vertices (SliceVertexCounter), which the
//    static core's time is proportional to (README: 2.3-4.1 us per slice vertex on every sequence measured).
//  - Checkpoint: with --checkpoint DIR every finished chunk is kept as DIR/chunk_<first>_<last>.pleatchunk
//    (written atomically by rank 0). A chunk file is used again only when its job key and its chunk key both
//    match. Job key: the command's output-determining options, the slicing plan's bytes (made from the first
//    requested frame, so a change there shows), the welded topology and vertex map, the frame count and
//    range, and the chunk bounds (which follow from the frames' measured costs). Chunk key: the job key and
//    the 64-bit fingerprints of the chunk's own frames (taken during the shared loading pass, no extra read).
//    So a changed frame invalidates its chunk (and, through the plan or the bounds, more when it changes
//    those); files of another job are removed, with a line on stderr.
//  - run_chunks(): computes this rank's chunks and hands rank 0 every frame's bytes in frame order.
//
// MPI calls are made from the main thread only (TBB works inside each rank): MPI_THREAD_FUNNELED.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sim_io/mesh_sequence.hpp"
#include "static_core/slicing_plan.hpp"
#include "support/fingerprint.hpp"

namespace pleat::cli {

/// The ranks of this job; one rank (and no MPI call at all) without mpirun.
class World {
 public:
  /// Initialises MPI when launched by mpirun; call once at the start of main.
  static void init(int& argc, char**& argv);
  /// Finalises MPI if it was initialised; call once at the end of main.
  static void finalize();
  static int rank();
  static int size();
  static bool root() { return rank() == 0; }
  static bool distributed() { return size() > 1; }
  /// Seconds since init() (each rank's own clock): when a frame finished, for --timings.
  static double seconds();
  /// Ends every rank of the job with `code` (one rank's error, e.g. an engine failure mid-chunk).
  [[noreturn]] static void abort(int code);
};

/// An error all ranks met or learnt of together (through agree()): rank 0 prints it, every rank exits with
/// `code` (2: bad input, 1: anything else), as a single process would.
class JobError : public std::runtime_error {
 public:
  JobError(const std::string& what, int code) : std::runtime_error(what), m_code(code) {}
  int code() const { return m_code; }

 private:
  int m_code;
};

/// Collective: every rank passes what it threw (or null). If any rank failed, every rank throws the JobError
/// of the lowest failing rank (ranks hold contiguous frame ranges in order, so that is the error of the
/// lowest frame, the one a single process meets first). With one rank, rethrows `error` as it is.
void agree(std::exception_ptr error);

/// Runs `step` on every rank and agree()s on what it threw: for steps every rank takes together.
template <class Step>
void together(Step&& step) {
  std::exception_ptr error;
  try {
    step();
  } catch (const JobError&) {
    throw;
  } catch (...) {
    error = std::current_exception();
  }
  agree(error);
}

/// A sequence loaded by every rank, the loading pass shared between them (LoadScan): rank r validates and
/// welds over the r-th equal share of all frames and fingerprints them; the weld classes are merged with one
/// MPI_Allreduce and the frame fingerprints gathered, so every rank ends with the same welding and all
/// fingerprints. Without mpirun: load_sequence, and fingerprints of every frame.
struct SharedSequence {
  MeshSequence sequence;
  std::vector<std::uint64_t> frame_fingerprints;  ///< one per frame of the input
  /// Fingerprint of the welded topology, the map to input vertices and the frame count (the frames have
  /// their own): what every chunk depends on besides its own frames and the plan.
  std::uint64_t welding_fingerprint() const;
};
SharedSequence load_shared(const std::filesystem::path& input, const std::filesystem::path& cache);

/// Every rank's bounding box lo/hi (3 doubles each) replaced by the box of all of them.
void all_reduce_bounds(double* lo, double* hi);
/// The same elementwise over arrays of float bounds (a rank leaves what it did not measure at +max / lowest).
void all_reduce_bounds(std::vector<float>& lo, std::vector<float>& hi);

/// The plan made by rank 0, sent to every rank (all ranks then slice with the same bits).
void broadcast_plan(SlicingPlan& plan);
std::uint64_t plan_fingerprint(const SlicingPlan& plan);

/// Frames [first, last) of `ranks` ranks: rank r's equal share by count.
std::pair<std::size_t, std::size_t> share_of(std::size_t first, std::size_t last, int rank, int ranks);

/// Number of slice vertices of a frame under `plan` (mesh edges crossing each plane): the cost measure of a
/// frame. O(E x orientations x log planes) per frame.
class SliceVertexCounter {
 public:
  SliceVertexCounter(const MeshTopology& topology, const SlicingPlan& plan);
  std::size_t count(const Frame& frame) const;

 private:
  std::vector<glm::dvec3> m_orientations;
  std::vector<std::vector<double>> m_offsets;  // per orientation, sorted
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

/// Finished chunks kept in a directory (see the file comment).
class Checkpoint {
 public:
  Checkpoint(std::filesystem::path dir, std::uint64_t job_key);
  /// Names and checks DIR's chunk files against the job: returns, per chunk, whether it is kept and valid;
  /// removes chunk files of another job (another input, plan or options) and says so on stderr.
  std::vector<bool> scan(const std::vector<std::size_t>& bounds,
                         const std::vector<std::uint64_t>& chunk_keys);
  std::filesystem::path path_of(std::size_t first, std::size_t last) const;
  const std::filesystem::path& dir() const { return m_dir; }
  std::uint64_t job_key() const { return m_job_key; }

 private:
  std::filesystem::path m_dir;
  std::uint64_t m_job_key;
};

/// One frame's result as bytes, and where it goes on rank 0.
using EmitFrame = std::function<void(std::size_t frame, std::string bytes)>;
/// Computes frames [first, last) (one chunk: a fresh engine), calling emit once per frame in order.
using ComputeChunk = std::function<void(std::size_t first, std::size_t last, const EmitFrame& emit)>;
/// On rank 0: every frame's bytes, in frame order.
using ConsumeFrame = std::function<void(std::size_t frame, std::string_view bytes)>;

struct ChunkJob {
  std::size_t first = 0, last = 0;  ///< the requested frames
  std::vector<std::size_t> bounds;  ///< absolute chunk boundaries: chunk c is [bounds[c], bounds[c+1])
  std::vector<int> owner;           ///< rank computing chunk c; -1: read from the checkpoint
  std::optional<Checkpoint> checkpoint;
  std::vector<std::uint64_t> chunk_keys;
  std::size_t kept_chunks = 0;  ///< chunks read from the checkpoint
};

/// Plans the chunks of frames [first, last) for the command: with one rank, no checkpoint and no --chunks,
/// one chunk (as before); else `chunks` chunks (0: one per rank) split by measured cost (SliceVertexCounter
/// over every frame, each rank counting its share), checked against the checkpoint and assigned to ranks.
/// Collective. `options_key` fingerprints the command's output-determining options; `cost_plan` may be null
/// (then every frame costs the same).
ChunkJob plan_chunks(const SharedSequence& input, std::size_t first, std::size_t last, std::size_t chunks,
                     const SlicingPlan* cost_plan, const std::string& checkpoint_dir,
                     std::uint64_t options_key);

/// Runs the job: this rank computes its chunks; rank 0 receives every frame's bytes (its own, the other
/// ranks', the checkpoint's) and passes them to `consume` in frame order, keeping finished chunks in the
/// checkpoint. Progress per rank and overall on rank 0's stderr as --progress says (auto: when rank 0's
/// stderr, or mpirun's, is a terminal).
void run_chunks(const ChunkJob& job, const std::string& what, const ComputeChunk& compute,
                const ConsumeFrame& consume);

/// Test hook (PLEAT_TEST_KILL_RANK=R): rank R raises SIGKILL after emitting its first frame.
void maybe_kill_for_test();

/// Appends / reads fixed-size values and byte strings (frame payloads).
class ByteWriter {
 public:
  template <class T>
  ByteWriter& put(const T& value) {
    m_bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
    return *this;
  }
  template <class T>
  ByteWriter& put_array(const std::vector<T>& values) {
    put<std::uint64_t>(values.size());
    m_bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    return *this;
  }
  ByteWriter& put_string(std::string_view text) {
    put<std::uint64_t>(text.size());
    m_bytes.append(text);
    return *this;
  }
  std::string take() { return std::move(m_bytes); }

 private:
  std::string m_bytes;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : m_bytes(bytes) {}
  template <class T>
  T get() {
    T value;
    need(sizeof value);
    std::memcpy(&value, m_bytes.data() + m_at, sizeof value);
    m_at += sizeof value;
    return value;
  }
  template <class T>
  std::vector<T> get_array() {
    const auto n = get<std::uint64_t>();
    need(n * sizeof(T));
    std::vector<T> values(n);
    std::memcpy(values.data(), m_bytes.data() + m_at, n * sizeof(T));
    m_at += n * sizeof(T);
    return values;
  }
  std::string_view get_string() {
    const auto n = get<std::uint64_t>();
    need(n);
    const std::string_view s = m_bytes.substr(m_at, n);
    m_at += n;
    return s;
  }

 private:
  void need(std::size_t n) const {
    if (m_bytes.size() - m_at < n) throw std::runtime_error("frame payload truncated");
  }
  std::string_view m_bytes;
  std::size_t m_at = 0;
};

}  // namespace pleat::cli
