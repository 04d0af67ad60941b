// The world over Open MPI (PLEAT_MPI=ON, or AUTO with Open MPI found): see cli/world.hpp.
#include "cli/world.hpp"

// The C API only (Open MPI's deprecated C++ bindings would need libmpi_cxx).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <deque>
#include <limits>
#include <stdexcept>
#include <utility>

#include "support/atomic_file.hpp"

namespace pleat::cli {

namespace {

bool g_mpi = false;
std::chrono::steady_clock::time_point g_start = std::chrono::steady_clock::now();
int g_rank = 0;
int g_size = 1;

void check(int status, const char* what) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

int count_of(std::size_t n) {
  if (n > std::size_t(std::numeric_limits<int>::max()))
    throw std::runtime_error("MPI: a message of more than 2^31 elements");
  return int(n);
}

// Sends of this rank still in flight (their buffers must live until they complete).
std::deque<std::pair<MPI_Request, std::string>> g_sends;

void reap_sends() {  // frees the buffers of completed sends at the front
  while (!g_sends.empty()) {
    int done = 0;
    check(MPI_Test(&g_sends.front().first, &done, MPI_STATUS_IGNORE), "Test");
    if (!done) return;
    g_sends.pop_front();
  }
}

MPI_Op op_of(World::Reduction op) {
  switch (op) {
    case World::Reduction::Min:
      return MPI_MIN;
    case World::Reduction::Max:
      return MPI_MAX;
    case World::Reduction::Sum:
      return MPI_SUM;
    case World::Reduction::BitXor:
      return MPI_BXOR;
  }
  throw std::logic_error("World::all_reduce: unknown reduction");
}

template <class T>
void reduce(std::span<T> values, MPI_Datatype type, World::Reduction op) {
  if (g_size == 1) return;
  check(MPI_Allreduce(MPI_IN_PLACE, values.data(), count_of(values.size()), type, op_of(op), MPI_COMM_WORLD),
        "Allreduce");
}

// The merge of the running all_reduce(block, merge), for the MPI_Op (a C function, no closure).
const World::Merge* g_merge = nullptr;
std::size_t g_merge_size = 0;
extern "C" void merge_blocks(void* in, void* inout, int* count, MPI_Datatype*) {
  auto* a = static_cast<const std::byte*>(in);
  auto* b = static_cast<std::byte*>(inout);
  for (int k = 0; k < *count; ++k, a += g_merge_size, b += g_merge_size) (*g_merge)(a, b, g_merge_size);
}

}  // namespace

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
int World::size() { return g_size; }
bool World::launched() { return g_mpi; }
bool World::built_with_mpi() { return true; }

double World::seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count();
}

void World::abort(int code) {
  remove_uncommitted_files();
  if (g_mpi) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

void World::broadcast(std::string& bytes, int root) {
  if (g_size == 1) return;
  auto length = std::uint64_t(bytes.size());
  check(MPI_Bcast(&length, 1, MPI_UINT64_T, root, MPI_COMM_WORLD), "Bcast");
  bytes.resize(length);
  check(MPI_Bcast(bytes.data(), count_of(length), MPI_BYTE, root, MPI_COMM_WORLD), "Bcast");
}

void World::all_reduce(std::span<int> values, Reduction op) { reduce(values, MPI_INT, op); }
void World::all_reduce(std::span<std::uint64_t> values, Reduction op) { reduce(values, MPI_UINT64_T, op); }
void World::all_reduce(std::span<float> values, Reduction op) { reduce(values, MPI_FLOAT, op); }
void World::all_reduce(std::span<double> values, Reduction op) { reduce(values, MPI_DOUBLE, op); }

void World::all_reduce(std::span<std::byte> block, const Merge& merge) {
  if (g_size == 1) return;
  MPI_Datatype block_type;
  check(MPI_Type_contiguous(count_of(block.size()), MPI_BYTE, &block_type), "Type_contiguous");
  MPI_Type_commit(&block_type);
  MPI_Op op;
  MPI_Op_create(&merge_blocks, /*commute=*/1, &op);
  g_merge = &merge, g_merge_size = block.size();
  std::string merged(block.size(), '\0');
  const int status = MPI_Allreduce(block.data(), merged.data(), 1, block_type, op, MPI_COMM_WORLD);
  g_merge = nullptr;
  MPI_Op_free(&op);
  MPI_Type_free(&block_type);
  check(status, "Allreduce");
  std::copy(merged.begin(), merged.end(), reinterpret_cast<char*>(block.data()));
}

void World::send(int to, int tag, std::string bytes) {
  if (to == g_rank || to < 0 || to >= g_size) throw std::logic_error("World::send: no such other rank");
  g_sends.emplace_back(MPI_REQUEST_NULL, std::move(bytes));
  auto& [request, buffer] = g_sends.back();
  check(MPI_Isend(buffer.data(), count_of(buffer.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD, &request),
        "Isend");
  reap_sends();
}

void World::wait_sends() {
  for (auto& [request, buffer] : g_sends) check(MPI_Wait(&request, MPI_STATUS_IGNORE), "Wait");
  g_sends.clear();
}

std::optional<World::Message> World::receive(int from, int tag, bool wait) {
  if (g_size == 1 || from == g_rank) throw std::logic_error("World::receive: no other rank to receive from");
  const int source = from == kAnyRank ? MPI_ANY_SOURCE : from;
  MPI_Status status;
  int flag = 1;
  if (wait)
    check(MPI_Probe(source, tag, MPI_COMM_WORLD, &status), "Probe");
  else
    check(MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &status), "Iprobe");
  if (!flag) return std::nullopt;
  int size = 0;
  check(MPI_Get_count(&status, MPI_BYTE, &size), "Get_count");
  Message message{status.MPI_SOURCE, std::string(std::size_t(size), '\0')};
  check(MPI_Recv(message.bytes.data(), size, MPI_BYTE, status.MPI_SOURCE, tag, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE),
        "Recv");
  return message;
}

}  // namespace pleat::cli
