// The world of one process (cli/world_single.cpp, the executable's world when built without MPI): one rank,
// collectives that leave the data as it is, point-to-point messages refused as logic errors, and a launch
// by mpirun of several ranks refused (rank 0 says why, every rank exits with 2).
#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/world.hpp"

namespace pleat {
namespace {

using cli::World;

TEST(WorldSingle, IsOneRankOfNoLauncher) {
  EXPECT_EQ(World::rank(), 0);
  EXPECT_EQ(World::size(), 1);
  EXPECT_TRUE(World::root());
  EXPECT_FALSE(World::distributed());
  EXPECT_FALSE(World::launched());
  EXPECT_FALSE(World::built_with_mpi());
  EXPECT_GE(World::seconds(), 0.0);
}

TEST(WorldSingle, CollectivesLeaveTheDataAsItIs) {
  std::string bytes = "abc";
  World::broadcast(bytes, 0);
  EXPECT_EQ(bytes, "abc");
  std::vector<double> values = {3.0, -1.0};
  World::all_reduce(std::span(values), World::Reduction::Sum);
  EXPECT_EQ(values, (std::vector<double>{3.0, -1.0}));
  std::vector<std::uint64_t> hashes = {7, 9};
  World::all_reduce(std::span(hashes), World::Reduction::BitXor);
  EXPECT_EQ(hashes, (std::vector<std::uint64_t>{7, 9}));
  std::vector<std::byte> block(4, std::byte{5});
  bool merged = false;
  World::all_reduce(std::span(block), [&](const std::byte*, std::byte*, std::size_t) { merged = true; });
  EXPECT_FALSE(merged);
  EXPECT_EQ(block, std::vector<std::byte>(4, std::byte{5}));
}

TEST(WorldSingle, MessagesToAnotherRankAreLogicErrors) {
  EXPECT_THROW(World::send(0, 1, "x"), std::logic_error);
  EXPECT_THROW(World::receive(World::kAnyRank, 1, false), std::logic_error);
  std::string bytes;
  EXPECT_THROW(World::broadcast(bytes, 1), std::logic_error);
  World::wait_sends();  // nothing in flight
}

TEST(WorldSingle, ALaunchOfSeveralRanksIsRefused) {
  int argc = 1;
  char name[] = "pleat";
  char* args[] = {name, nullptr};
  char** argv = args;
  auto launch = [&](const char* rank) {
    setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
    setenv("OMPI_COMM_WORLD_RANK", rank, 1);
    World::init(argc, argv);
  };
  EXPECT_EXIT(launch("0"), testing::ExitedWithCode(2), "built without MPI");
  EXPECT_EXIT(launch("1"), testing::ExitedWithCode(2), "^$");
  // One rank of one: runs.
  setenv("OMPI_COMM_WORLD_SIZE", "1", 1);
  World::init(argc, argv);
  unsetenv("OMPI_COMM_WORLD_SIZE");
  unsetenv("OMPI_COMM_WORLD_RANK");
  EXPECT_EQ(World::size(), 1);
}

}  // namespace
}  // namespace pleat
