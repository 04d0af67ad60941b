// The world of one process, in a pleat built without MPI (PLEAT_MPI=OFF, or AUTO without Open MPI): see
// cli/world.hpp.
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

#include "cli/world.hpp"
#include "support/atomic_file.hpp"

namespace pleat::cli {

namespace {

std::chrono::steady_clock::time_point g_start = std::chrono::steady_clock::now();

int environment_number(const char* name) {
  const char* value = std::getenv(name);
  return value ? std::atoi(value) : 0;
}

[[noreturn]] void no_other_rank(const char* what) {
  throw std::logic_error(std::string("World::") + what + ": a job of one rank has no other rank");
}

}  // namespace

void World::init(int&, char**&) {
  g_start = std::chrono::steady_clock::now();
  // Under mpirun every rank would compute and write the whole job: refused, said once (by rank 0).
  if (environment_number("OMPI_COMM_WORLD_SIZE") > 1) {
    if (environment_number("OMPI_COMM_WORLD_RANK") == 0)
      std::cerr << "pleat: error: this pleat was built without MPI (PLEAT_MPI=OFF), so it cannot run as "
                   "several ranks: run it without mpirun, or build it with Open MPI (libopenmpi-dev)\n";
    std::exit(2);
  }
}

void World::finalize() {}
int World::rank() { return 0; }
int World::size() { return 1; }
bool World::launched() { return false; }
bool World::built_with_mpi() { return false; }

double World::seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count();
}

void World::abort(int code) {
  remove_uncommitted_files();
  std::exit(code);
}

void World::broadcast(std::string&, int root) {
  if (root != 0) no_other_rank("broadcast");
}
void World::all_reduce(std::span<int>, Reduction) {}
void World::all_reduce(std::span<std::uint64_t>, Reduction) {}
void World::all_reduce(std::span<float>, Reduction) {}
void World::all_reduce(std::span<double>, Reduction) {}
void World::all_reduce(std::span<std::byte>, const Merge&) {}

void World::send(int, int, std::string) { no_other_rank("send"); }
void World::wait_sends() {}
std::optional<World::Message> World::receive(int, int, bool) { no_other_rank("receive"); }

}  // namespace pleat::cli
