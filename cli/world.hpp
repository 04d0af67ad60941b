// The ranks of a job and the few ways they talk: the processes `mpirun -np N pleat ...` starts, or one
// process alone. Two implementations, chosen at configure time (PLEAT_MPI): world_mpi.cpp (Open MPI,
// initialised only when launched by mpirun, i.e. with Open MPI's OMPI_COMM_WORLD_SIZE or PMIx's PMIX_RANK in
// the environment; otherwise a world of one rank that makes no MPI call) and world_single.cpp (no MPI at
// all: always one rank). Only world_mpi.cpp includes <mpi.h>.
//
// Every call is made from the main thread (TBB works inside each rank): MPI_THREAD_FUNNELED. Collectives
// (broadcast, all_reduce) are called by every rank in the same order; with one rank they return at once and
// leave the data as it is. Point-to-point messages (send, receive) need another rank: with one rank they are
// a logic error (std::logic_error). A failed MPI call throws std::runtime_error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>

namespace pleat::cli {

class World {
 public:
  /// Initialises MPI when launched by mpirun; call once at the start of main. Without MPI built in, a
  /// launch by mpirun of more than one rank is refused: rank 0 says so on stderr, every rank exits with 2.
  static void init(int& argc, char**& argv);
  /// Finalises MPI if it was initialised; call once at the end of main.
  static void finalize();
  static int rank();
  static int size();
  static bool root() { return rank() == 0; }
  static bool distributed() { return size() > 1; }
  /// Whether a launcher (mpirun) started this process, even as a job of one rank.
  static bool launched();
  /// Whether this pleat was built with MPI (PLEAT_MPI).
  static bool built_with_mpi();
  /// Seconds since init() (each rank's own clock): when a frame finished, for --timings.
  static double seconds();
  /// Ends every rank of the job with `code` (one rank's error, e.g. an engine failure mid-chunk), after
  /// removing this process's uncommitted output files (support/atomic_file.hpp).
  [[noreturn]] static void abort(int code);

  // ---- Collectives ----

  /// `bytes` of rank `root` replaces every rank's (any length).
  static void broadcast(std::string& bytes, int root);

  enum class Reduction { Min, Max, Sum, BitXor };
  /// Every rank's `values` replaced by their elementwise reduction over all ranks (equal lengths on every
  /// rank). BitXor for integers only.
  static void all_reduce(std::span<int> values, Reduction op);
  static void all_reduce(std::span<std::uint64_t> values, Reduction op);
  static void all_reduce(std::span<float> values, Reduction op);
  static void all_reduce(std::span<double> values, Reduction op);

  /// merge(in, inout, size): combines the block `in` into the block `inout` (both `size` bytes). It must be
  /// associative and commutative (the ranks' blocks are combined in no fixed order).
  using Merge = std::function<void(const std::byte* in, std::byte* inout, std::size_t size)>;
  /// Every rank's `block` (equal sizes on every rank) replaced by the merge of all ranks' blocks.
  static void all_reduce(std::span<std::byte> block, const Merge& merge);

  // ---- Point to point ----

  static constexpr int kAnyRank = -1;
  struct Message {
    int source = 0;
    std::string bytes;
  };
  /// Sends `bytes` to rank `to` (not this one) under `tag` without waiting: the bytes are kept until
  /// delivered. Messages from one rank under one tag arrive in the order sent.
  static void send(int to, int tag, std::string bytes);
  /// Waits until every send of this rank is delivered.
  static void wait_sends();
  /// The next message under `tag` from rank `from` (kAnyRank: any other rank): waits for one when `wait`,
  /// else returns nothing when none has arrived.
  static std::optional<Message> receive(int from, int tag, bool wait);
};

}  // namespace pleat::cli
