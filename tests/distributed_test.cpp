// Scale-out over MPI ranks (cli/chunk_plan.hpp, cli/run_chunks.hpp, issue 16): the chunk split and
// assignment, and the executable under `mpirun --oversubscribe -np 2|3` on one machine: the same bytes as one
// process for both engines and for shading, a killed rank leaves no output, a rerun with --checkpoint
// computes only the missing chunks, bad input fails once with the single process's message. The mpirun runs
// are skipped in a build without MPI (PLEAT_MPI=OFF), where a launch by mpirun is refused instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli/chunk_plan.hpp"
#include "cli/shared_load.hpp"
#include "cli/world.hpp"
#include "sim_io/load_sequence.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::names_in;
using test::slurp;

using test::CommandResult;
using test::TempDir;

/// In the sanitizer build, the LeakSanitizer options of every rank: Open MPI's suppressions, and the slow
/// unwinder so that an allocation made inside Open MPI's libraries is seen to be theirs (tests/sanitizer/).
#ifdef PLEAT_MPI_LSAN_OPTIONS
const std::string kRankSanitizerEnv = "LSAN_OPTIONS=" PLEAT_MPI_LSAN_OPTIONS " ";
#else
const std::string kRankSanitizerEnv;
#endif

/// The mpirun runs need a pleat built with MPI.
#define PLEAT_NEEDS_MPI() \
  if (!cli::World::built_with_mpi()) GTEST_SKIP() << "pleat is built without MPI (PLEAT_MPI=OFF)"

/// `mpirun -np N pleat ARGS` on this machine, as root or not; `env` (NAME=VALUE) is passed to every rank.
CommandResult mpirun(int ranks, const std::string& args, const std::string& env = "") {
  return test::run_command(kRankSanitizerEnv + "mpirun --allow-run-as-root --oversubscribe -np " +
                           std::to_string(ranks) + (env.empty() ? "" : " -x " + env) + " " +
                           PLEAT_EXECUTABLE + " " + args);
}

/// Files of `dir` (names), to check that a failed run left nothing behind.
/// A generated curtain of 7 frames (uneven over 2 and 3 ranks) in `dir`: "c.obj --cache c.pc2".
std::string make_curtain(const TempDir& dir, int resolution = 10, int frames = 7) {
  const auto made = test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution " +
                                    std::to_string(resolution) + " --frames " + std::to_string(frames));
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string();
}

TEST(Distributed, SplitByCostGivesContiguousNonEmptyChunksOfNearlyEqualCost) {
  const std::vector<double> cost = {1, 1, 1, 1, 8, 1, 1, 1, 1, 8};
  const auto bounds = cli::split_by_cost(cost, 4);
  ASSERT_EQ(bounds.size(), 5u);
  EXPECT_EQ(bounds.front(), 0u);
  EXPECT_EQ(bounds.back(), cost.size());
  for (std::size_t c = 0; c + 1 < bounds.size(); ++c) EXPECT_LT(bounds[c], bounds[c + 1]);
  EXPECT_EQ(bounds[1], 4u);  // the first chunk ends before the expensive frame 4 (total 24: 6 each)
  EXPECT_EQ(bounds[3], 9u);  // the expensive frame 9 is a chunk of its own
  // More chunks than frames: one frame each; no cost at all: by count.
  EXPECT_EQ(cli::split_by_cost({1, 2, 3}, 10), (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_EQ(cli::split_by_cost({0, 0, 0, 0}, 2), (std::vector<std::size_t>{0, 2, 4}));
}

TEST(Distributed, TheCostMeasureCountsTheSliceVerticesTheEngineMakes) {
  TempDir dir;
  make_curtain(dir);
  ASSERT_EQ(
      test::run_pleat("visibility " + (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string() +
                      " -o " + (dir / "v.csv").string() + " --stats " + (dir / "s.json").string())
          .exit_code,
      0);
  const auto stats = nlohmann::json::parse(slurp(dir / "s.json"));
  const MeshSequence sequence = load_sequence(dir / "c.obj", dir / "c.pc2");
  const SlicingPlan plan =
      make_diffuse_plan(sequence.topology(), sequence.frame(0), DiffusePlanParams{}, &sequence.bounds());
  const cli::SliceVertexCounter counter(sequence.topology(), plan);
  ASSERT_EQ(stats["frames"].size(), sequence.num_frames());
  for (std::size_t f = 0; f < sequence.num_frames(); ++f)
    EXPECT_EQ(counter.count(sequence.frame(f)), stats["frames"][f]["slice_vertices"].get<std::size_t>()) << f;
}

/// A frame source that records which frames were read.
class RecordingSource : public FrameSource {
 public:
  explicit RecordingSource(std::vector<std::size_t>* reads) : m_reads(reads) {}
  std::size_t num_frames() const override { return 6; }
  double frame_time(std::size_t i) const override { return double(i); }
  std::vector<glm::dvec3> read_frame(std::size_t i) const override {
    m_reads->push_back(i);
    return {{0, 0, 0}, {1, 0, double(i)}, {0, 1, 0}};
  }

 private:
  std::vector<std::size_t>* m_reads;
};

TEST(Distributed, ALoadScanReadsOnlyItsShareOfTheFrames) {
  std::vector<std::size_t> reads;
  LoadScan scan;
  scan.range = [](std::size_t n) { return cli::share_of(0, n, 1, 3); };  // rank 1 of 3: frames 2 and 3
  bool merged = false;
  scan.merge = [&](std::vector<Index>& classes, std::exception_ptr error) {
    EXPECT_FALSE(error);
    EXPECT_EQ(classes, (std::vector<Index>{0, 1, 2}));
    merged = true;
  };
  const MeshSequence sequence("t", {{0, 1, 2}}, 3, std::make_unique<RecordingSource>(&reads), scan);
  EXPECT_EQ(reads, (std::vector<std::size_t>{2, 3}));
  EXPECT_TRUE(merged);
  EXPECT_EQ(sequence.num_frames(), 6u);
}

TEST(Distributed, AssignChunksGivesEachRankAContiguousRunOfTheMissingChunks) {
  const std::vector<double> cost = {1, 1, 1, 1, 1, 1};
  const std::vector<bool> todo = {true, false, true, true, false, true};
  const auto owner = cli::assign_chunks(cost, todo, 2);
  EXPECT_EQ(owner, (std::vector<int>{0, -1, 0, 1, -1, 1}));
  EXPECT_EQ(cli::assign_chunks({5, 1, 1, 1, 1, 1}, std::vector<bool>(6, true), 2),
            (std::vector<int>{0, 1, 1, 1, 1, 1}));  // balanced by cost, not count
}

TEST(Distributed, BothEnginesAtTwoAndThreeRanksWriteTheBytesOfOneProcess) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  for (const std::string engine : {"kinetic", "static"}) {
    const std::string one = (dir / ("one_" + engine)).string();
    const auto single = test::run_pleat("visibility " + input + " --engine " + engine + " -o " + one +
                                        ".csv --stats " + one + ".json --frames 0:7");
    ASSERT_EQ(single.exit_code, 0) << single.output;
    int run_index = 0;
    for (const auto& [ranks, extra] : {std::pair{2, ""}, std::pair{3, ""}, std::pair{2, " --chunks 5"}}) {
      const std::string out = (dir / (engine + std::to_string(run_index++))).string();
      const auto many =
          mpirun(ranks, "visibility " + input + " --engine " + engine + " -o " + out + ".csv --stats " + out +
                            ".json --timings " + out + "_timings.json --frames 0:7" + extra);
      ASSERT_EQ(many.exit_code, 0) << many.output;
      EXPECT_TRUE(slurp(one + ".csv") == slurp(out + ".csv"))
          << engine << " at " << ranks << " ranks" << extra;
      EXPECT_TRUE(slurp(one + ".json") == slurp(out + ".json"))
          << engine << " at " << ranks << " ranks" << extra;
      EXPECT_NE(slurp(out + "_timings.json").find("\"chunk_start\""), std::string::npos);
    }
  }
}

TEST(Distributed, TheProgressCountsTheFramesOfEveryRank) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  const auto run = mpirun(2, "visibility " + input + " -o " + (dir / "v.csv").string() + " --progress lines");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // Rank 1's frames reach rank 0's line through its progress messages, to the last.
  EXPECT_NE(run.output.find("7/7 frames 100.0%"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("r0 4/4  r1 3/3"), std::string::npos) << run.output;
}

TEST(Distributed, OccludersAtTwoRanksGiveTheBytesOfOneProcess) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  const std::string scene =
      " --ground z=0 --occluder " + std::string(PLEAT_SOURCE_DIR) + "/data/rucked/rucked_colliders.obj";
  const std::string one = (dir / "one.csv").string(), two = (dir / "two.csv").string();
  const auto single = test::run_pleat("visibility " + input + scene + " --frames 1:7 -o " + one);
  ASSERT_EQ(single.exit_code, 0) << single.output;
  const auto many = mpirun(2, "visibility " + input + scene + " --frames 1:7 -o " + two);
  ASSERT_EQ(many.exit_code, 0) << many.output;
  EXPECT_TRUE(slurp(one) == slurp(two));
  const auto alone =
      test::run_pleat("visibility " + input + " --frames 1:7 -o " + (dir / "alone.csv").string());
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  EXPECT_FALSE(slurp(one) == slurp(dir / "alone.csv"));  // the scene changes the values
}

TEST(Distributed, ShadeAtTwoAndThreeRanksWritesTheGlbAndImagesOfOneProcess) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  const std::string lights =
      " --light sky:0.5 --light point:0.5,-1,1.5,I=2 --frames 1:7 -q --render-every 2 --width 64 --height 48";
  const auto single = test::run_pleat("shade " + input + " -o " + (dir / "one.glb").string() + lights +
                                      " --render " + (dir / "one").string());
  ASSERT_EQ(single.exit_code, 0) << single.output;
  const auto images = names_in(dir / "one");
  ASSERT_EQ(images.size(), 3u);
  for (int ranks : {2, 3}) {
    const std::string out = (dir / ("many" + std::to_string(ranks))).string();
    const auto many = mpirun(ranks, "shade " + input + " -o " + out + ".glb" + lights + " --render " + out);
    ASSERT_EQ(many.exit_code, 0) << many.output;
    EXPECT_TRUE(slurp(dir / "one.glb") == slurp(out + ".glb")) << ranks << " ranks";
    ASSERT_EQ(names_in(out), images);
    for (const std::string& image : images)
      EXPECT_TRUE(slurp(dir / "one" / image) == slurp(std::filesystem::path(out) / image)) << image;
  }
  // With a checkpoint: a rerun keeps every chunk and writes the same glb.
  const std::string checkpointed = "shade " + input + " -o " + (dir / "ck.glb").string() + lights +
                                   " --chunks 3 --checkpoint " + (dir / "ck").string();
  ASSERT_EQ(mpirun(2, checkpointed).exit_code, 0);
  std::filesystem::remove(dir / "ck.glb");
  const auto rerun = mpirun(3, checkpointed);
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  EXPECT_TRUE(slurp(dir / "one.glb") == slurp(dir / "ck.glb"));
}

TEST(Distributed, TheConeCacheAtTwoAndThreeRanksAndFromACheckpointIsTheOneOfOneProcess) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  const std::string one = (dir / "one").string();
  const auto single =
      test::run_pleat("visibility " + input + " -o " + one + ".csv --cones " + one + ".cones --frames 1:7");
  ASSERT_EQ(single.exit_code, 0) << single.output;
  const std::string cones = slurp(one + ".cones");
  ASSERT_GT(cones.size(), 6u * 100 * 8);  // six frames of a 100-vertex cloth's cones
  for (int ranks : {2, 3}) {
    const std::string out = (dir / ("many" + std::to_string(ranks))).string();
    const auto many = mpirun(ranks, "visibility " + input + " -o " + out + ".csv --cones " + out +
                                        ".cones --frames 1:7 --chunks 4");
    ASSERT_EQ(many.exit_code, 0) << many.output;
    EXPECT_TRUE(slurp(out + ".cones") == cones) << ranks << " ranks";
    EXPECT_TRUE(slurp(out + ".csv") == slurp(one + ".csv")) << ranks << " ranks";
  }
  // Chunks kept by a checkpoint carry their cones: a rerun that computes nothing writes the same cache, and a
  // checkpoint made without --cones is not taken for one with them.
  const std::string plain = "visibility " + input + " -o " + (dir / "ck.csv").string() +
                            " --frames 1:7 --chunks 3 --checkpoint " + (dir / "ck").string();
  ASSERT_EQ(mpirun(2, plain).exit_code, 0);
  const std::string with_cones = plain + " --cones " + (dir / "ck.cones").string();
  const auto first = mpirun(2, with_cones);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_EQ(first.output.find("kept from the checkpoint"), std::string::npos) << first.output;
  std::filesystem::remove(dir / "ck.cones");
  const auto rerun = test::run_pleat(with_cones);
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  EXPECT_NE(rerun.output.find("3 kept from the checkpoint"), std::string::npos) << rerun.output;
  EXPECT_TRUE(slurp(dir / "ck.cones") == cones);
}

TEST(Distributed, AKilledRankFailsTheJobAndLeavesNoOutput) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  std::filesystem::create_directories(dir / "out");
  const auto before = names_in(dir / "out");
  for (const std::string command : {"visibility", "shade"}) {
    const std::string out = (dir / "out" / (command == "shade" ? "v.glb" : "v.csv")).string();
    const std::string extra = command == "visibility" ? " --stats " + (dir / "out/s.json").string() +
                                                            " --cones " + (dir / "out/c.cones").string()
                                                      : "";
    const auto killed = mpirun(2, command + " " + input + " -o " + out + extra, "PLEAT_TEST_KILL_RANK=1");
    EXPECT_NE(killed.exit_code, 0) << killed.output;
    EXPECT_EQ(names_in(dir / "out"), before) << command << ": " << killed.output;
  }
}

TEST(Distributed, ARerunWithTheCheckpointComputesOnlyTheMissingChunks) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  const std::string single = (dir / "one.csv").string();
  ASSERT_EQ(test::run_pleat("visibility " + input + " -o " + single).exit_code, 0);
  const std::string args = "visibility " + input + " -o " + (dir / "v.csv").string() +
                           " --chunks 4 --checkpoint " + (dir / "ck").string();
  // A rank killed after its first frame: no output; whatever chunks were finished are kept.
  const auto killed = mpirun(2, args, "PLEAT_TEST_KILL_RANK=1");
  EXPECT_NE(killed.exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "v.csv"));
  // The rerun finishes the job; then one chunk is lost and the next rerun computes only it.
  const auto rerun = mpirun(2, args);
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  EXPECT_TRUE(slurp(dir / "v.csv") == slurp(single));
  std::vector<std::filesystem::path> chunks;
  for (const auto& e : std::filesystem::directory_iterator(dir / "ck")) chunks.push_back(e.path());
  ASSERT_EQ(chunks.size(), 4u);
  std::sort(chunks.begin(), chunks.end());
  std::filesystem::remove(chunks[2]);
  std::filesystem::remove(dir / "v.csv");
  const auto third = mpirun(3, args);
  ASSERT_EQ(third.exit_code, 0) << third.output;
  EXPECT_NE(third.output.find("4 chunks over 3 ranks, 3 kept from the checkpoint"), std::string::npos)
      << third.output;
  EXPECT_TRUE(slurp(dir / "v.csv") == slurp(single));
  // One process too, with everything kept.
  const auto fourth = test::run_pleat(args);
  ASSERT_EQ(fourth.exit_code, 0) << fourth.output;
  EXPECT_NE(fourth.output.find("4 kept from the checkpoint"), std::string::npos) << fourth.output;
  EXPECT_TRUE(slurp(dir / "v.csv") == slurp(single));
}

TEST(Distributed, AChangedInputOrPlanInvalidatesTheCheckpoint) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  const std::string args = "visibility " + input + " -o " + (dir / "v.csv").string() +
                           " --chunks 3 --checkpoint " + (dir / "ck").string();
  ASSERT_EQ(mpirun(2, args).exit_code, 0);
  // Another plan: nothing kept.
  const auto replanned = mpirun(2, args + " --orientations 6");
  ASSERT_EQ(replanned.exit_code, 0) << replanned.output;
  EXPECT_EQ(replanned.output.find("kept from the checkpoint"), std::string::npos) << replanned.output;
  // One frame of the cache changed (last byte of the last frame): its chunk alone is computed again.
  {
    std::fstream pc2(dir / "c.pc2", std::ios::in | std::ios::out | std::ios::binary);
    pc2.seekg(-2, std::ios::end);
    char byte = 0;
    pc2.read(&byte, 1);
    byte ^= 1;
    pc2.seekp(-2, std::ios::end);
    pc2.write(&byte, 1);
  }
  const auto changed = mpirun(2, args + " --orientations 6");
  ASSERT_EQ(changed.exit_code, 0) << changed.output;
  EXPECT_NE(changed.output.find("3 chunks over 2 ranks, 2 kept from the checkpoint"), std::string::npos)
      << changed.output;
}

// How often `text` holds `part`.
std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(Distributed, CommandsThatDoNotSplitTheirWorkRunOnOneRank) {
  // info, generate, compare and view under `mpirun -np N`: rank 0 does the work once, the others wait and end
  // with its exit status; bad input is reported once.
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir);
  const auto info = mpirun(3, "info " + input);
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_EQ(occurrences(info.output, "\nvertices "), 1u) << info.output;
  const auto generated =
      mpirun(2, "generate flag -o " + (dir / "f.obj").string() + " --resolution 6 --frames 3");
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  EXPECT_EQ(occurrences(generated.output, "wrote "), 2u) << generated.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "f.pc2"));
  const auto compared =
      mpirun(2, "compare " + input + " --light sky:1 --paths 16 --width 48 --height 36 -o " +
                    (dir / "cmp.png").string());
  ASSERT_EQ(compared.exit_code, 0) << compared.output;
  EXPECT_EQ(occurrences(compared.output, "wrote " + (dir / "cmp.png").string()), 1u) << compared.output;
  EXPECT_EQ(names_in(dir.path()), (std::vector<std::string>{"c.obj", "c.pc2", "cmp.png", "f.obj", "f.pc2"}));
  const auto missing = mpirun(3, "info " + (dir / "missing.obj").string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_EQ(occurrences(missing.output, "missing.obj: no such file"), 1u) << missing.output;
}

TEST(Distributed, WithoutMpiALaunchByMpirunIsRefusedOnceWithoutOutput) {
  if (cli::World::built_with_mpi()) GTEST_SKIP() << "pleat is built with MPI";
  TempDir dir;
  const std::string input = make_curtain(dir);
  const std::string args = " visibility " + input + " -o " + (dir / "v.csv").string();
  const std::string refusal = "pleat: error: this pleat was built without MPI";
  // What mpirun gives each rank of two: rank 0 says why, every rank exits with 2.
  for (int rank : {0, 1}) {
    const auto run = test::run_command("OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=" + std::to_string(rank) +
                                       " " + PLEAT_EXECUTABLE + args);
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_EQ(run.output.find(refusal) != std::string::npos, rank == 0) << run.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "v.csv"));
  }
  // A job of one rank is one process.
  const auto one = test::run_command("OMPI_COMM_WORLD_SIZE=1 OMPI_COMM_WORLD_RANK=0 " +
                                     std::string(PLEAT_EXECUTABLE) + args);
  EXPECT_EQ(one.exit_code, 0) << one.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "v.csv"));
}

/// The generated curtain with vertex 0 split in two at its first face (as exporters split seams): the copy
/// coincides with it in every frame (`split_from` = 7) or only up to frame `split_from`.
std::string make_split_curtain(const TempDir& dir, int split_from) {
  make_curtain(dir);
  std::ifstream obj_in(dir / "c.obj");
  std::ofstream obj_out(dir / "s.obj");
  bool split = false;
  for (std::string line; std::getline(obj_in, line);) {
    if (!split && line == "f 1 2 12") line = "f 101 2 12", split = true;
    obj_out << line << '\n';
  }
  EXPECT_TRUE(split);
  std::ifstream first_vertex(dir / "c.obj");
  std::string line;
  while (std::getline(first_vertex, line) && line.rfind("v ", 0) != 0) {
  }
  obj_out << line << '\n';
  obj_out.close();
  const std::string pc2 = slurp(dir / "c.pc2");
  std::string header = pc2.substr(0, 32);
  const std::int32_t points = 101;
  std::memcpy(header.data() + 16, &points, 4);
  std::string out = header;
  for (int f = 0; f < 7; ++f) {
    std::string frame = pc2.substr(32 + std::size_t(f) * 1200, 1200);
    std::string copy = frame.substr(0, 12);
    if (f >= split_from) copy[11] ^= 0x10;  // a different z
    out += frame + copy;
  }
  std::ofstream(dir / "s.pc2", std::ios::binary) << out;
  return (dir / "s.obj").string() + " --cache " + (dir / "s.pc2").string();
}

TEST(Distributed, WeldingOverSharedLoadingEqualsOneProcess) {
  PLEAT_NEEDS_MPI();
  for (int split_from : {7, 5}) {
    TempDir dir;
    const std::string input = make_split_curtain(dir, split_from);
    const auto info = test::run_pleat("info " + input);
    EXPECT_NE(info.output.find(split_from == 7 ? "1 welded" : "0 welded"), std::string::npos) << info.output;
    const auto single = test::run_pleat("visibility " + input + " -o " + (dir / "one.csv").string());
    ASSERT_EQ(single.exit_code, 0) << single.output;
    const auto many = mpirun(3, "visibility " + input + " -o " + (dir / "three.csv").string());
    ASSERT_EQ(many.exit_code, 0) << many.output;
    EXPECT_TRUE(slurp(dir / "one.csv") == slurp(dir / "three.csv")) << "split from frame " << split_from;
  }
}

TEST(Distributed, BadInputFailsOnceWithTheSingleProcessMessageAndNoOutput) {
  PLEAT_NEEDS_MPI();
  TempDir dir;
  const std::string input = make_curtain(dir, 6, 7);
  {
    // A NaN in the last frame (read by the last rank's share of the loading pass).
    std::fstream pc2(dir / "c.pc2", std::ios::in | std::ios::out | std::ios::binary);
    pc2.seekp(32 + 6 * 36 * 12 + 4);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    pc2.write(reinterpret_cast<const char*>(&nan), 4);
  }
  const auto single = test::run_pleat("visibility " + input + " -o " + (dir / "v.csv").string());
  ASSERT_EQ(single.exit_code, 2);
  const std::string message = single.output.substr(0, single.output.find('\n'));
  EXPECT_NE(message.find("c.pc2"), std::string::npos) << message;
  for (int ranks : {2, 3}) {
    const auto many = mpirun(ranks, "visibility " + input + " -o " + (dir / "v.csv").string());
    EXPECT_NE(many.exit_code, 0);
    const auto at = many.output.find(message);
    EXPECT_NE(at, std::string::npos) << many.output;
    EXPECT_EQ(many.output.find(message, at + 1), std::string::npos) << "reported more than once";
    EXPECT_FALSE(std::filesystem::exists(dir / "v.csv"));
  }
}

}  // namespace
}  // namespace pleat
