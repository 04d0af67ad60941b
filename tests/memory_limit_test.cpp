// Runs under a batch system's memory limit (cli/memory_limit.hpp): a frame that cannot fit is refused before
// any work, saying what it needs; running out of memory anyway ends with exit status 1 and "out of memory",
// never an abort (--threads 1 included); the limit is read from RLIMIT_AS and from the memory cgroup (v1
// and v2 layouts). Real processes under setrlimit.
#include "cli/memory_limit.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "cli/chunk_plan.hpp"
#include "sim_io/cloth_generators.hpp"
#include "static_core/slicing_plan.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::slurp;
namespace fs = std::filesystem;

#ifdef PLEAT_SANITIZED
#define PLEAT_NEEDS_ADDRESS_LIMITS() \
  GTEST_SKIP() << "the sanitizers reserve more address space than any limit"
#else
#define PLEAT_NEEDS_ADDRESS_LIMITS()
#endif

// Runs `pleat ARGS` under an address-space limit of `megabytes`; returns the wait status.
int run_limited(const std::vector<std::string>& args, std::uint64_t megabytes, const fs::path& errors) {
  const rlimit limit{megabytes << 20, megabytes << 20};
  const pid_t pid = test::start_pleat(args, errors, {.limits = {{RLIMIT_AS, limit}}});
  int status = 0;
  EXPECT_EQ(::waitpid(pid, &status, 0), pid);
  return status;
}

TEST(MemoryLimit, AFrameThatCannotFitIsRefusedBeforeAnyWork) {
  // About 2.2 million slice vertices: a frame needs about 1 GB, under a limit of 600 MB.
  PLEAT_NEEDS_ADDRESS_LIMITS();
  test::TempDir dir;
  ASSERT_EQ(
      test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 300 --frames 2")
          .exit_code,
      0);
  for (const std::string threads : {"1", "2"}) {
    SCOPED_TRACE(threads + " threads");
    const int status =
        run_limited({"visibility", (dir / "c.obj").string(), "--cache", (dir / "c.pc2").string(), "-o",
                     (dir / "v.csv").string(), "--threads", threads},
                    600, dir / "errors.txt");
    const std::string errors = slurp(dir / "errors.txt");
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status) << ": " << errors;
    EXPECT_EQ(WEXITSTATUS(status), 1) << errors;
    EXPECT_NE(errors.find("pleat: error: out of memory before starting: frame 0 needs about "),
              std::string::npos)
        << errors;
    const std::regex need(" GB \\(2\\.2 million slice vertices over [0-9]+ planes, " + threads +
                          (threads == "1" ? " thread" : " threads") +
                          "\\), and the memory limit of 600 MB \\(ulimit -v\\) leaves [0-9]+ MB; ");
    EXPECT_TRUE(std::regex_search(errors, need)) << errors;
    EXPECT_NE(errors.find("--spacing-edges"), std::string::npos) << errors;
    EXPECT_FALSE(fs::exists(dir / "v.csv"));
    EXPECT_EQ(test::names_in(dir.path()), (std::vector<std::string>{"c.obj", "c.pc2", "errors.txt"}));
  }
}

TEST(MemoryLimit, RunningOutOfMemoryEndsWithExitStatusOneNeverAnAbort) {
  // A limit the process reaches while it works (a render of 16384 x 16384 pixels is not in the estimate),
  // and one it reaches while loading: "out of memory", exit status 1, no SIGABRT at exit with --threads 1
  // (the thread limit's destructor once threw there), no output.
  PLEAT_NEEDS_ADDRESS_LIMITS();
  test::TempDir dir;
  ASSERT_EQ(test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 30 --frames 2")
                .exit_code,
            0);
  const std::vector<std::string> render = {"shade",     (dir / "c.obj").string(),
                                           "--cache",   (dir / "c.pc2").string(),
                                           "-o",        (dir / "s.glb").string(),
                                           "--render",  (dir / "r").string(),
                                           "--width",   "16384",
                                           "--height",  "16384",
                                           "--threads", "1"};
  const int status = run_limited(render, 600, dir / "errors.txt");
  const std::string errors = slurp(dir / "errors.txt");
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status) << ": " << errors;
  EXPECT_EQ(WEXITSTATUS(status), 1) << errors;
  EXPECT_NE(errors.find("pleat: error: out of memory; the memory limit is 600 MB (ulimit -v)"),
            std::string::npos)
      << errors;
  EXPECT_EQ(errors.find("std::bad_alloc"), std::string::npos) << errors;
  EXPECT_FALSE(fs::exists(dir / "s.glb"));
  EXPECT_TRUE(!fs::exists(dir / "r") || fs::is_empty(dir / "r"));
}

// A fake /proc/self/cgroup and cgroup file system under `root`.
void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

TEST(MemoryLimit, TheLimitOfTheMemoryCgroupAndItsAncestors) {
  test::TempDir dir;
  const fs::path proc = dir / "proc", root = dir / "sys";
  // cgroup v1: the job's cgroup has no limit of its own, its parent (the batch system's) has 2 GB; the use
  // counted is the cgroup's, page cache aside.
  write_file(proc / "cgroup", "4:memory:/slurm/job_7\n3:cpu:/\n0::/\n");
  write_file(root / "memory/slurm/job_7/memory.limit_in_bytes", "9223372036854771712\n");
  write_file(root / "memory/slurm/job_7/memory.usage_in_bytes", "600000000\n");
  write_file(root / "memory/slurm/job_7/memory.stat",
             "cache 100000000\nrss 400000000\ntotal_cache 200000000\n");
  write_file(root / "memory/slurm/memory.limit_in_bytes", "2147483648\n");
  write_file(root / "memory/slurm/memory.usage_in_bytes", "900000000\n");
  auto limit = cli::memory_limit(proc, root);
  ASSERT_TRUE(limit.has_value());
  EXPECT_EQ(limit->bytes, 2147483648u);
  EXPECT_EQ(limit->used, 900000000u);
  EXPECT_FALSE(limit->address_space);
  EXPECT_EQ(limit->source, "the memory cgroup's memory.limit_in_bytes");
  // cgroup v2: "max" at the job, 1 GB at the parent.
  write_file(proc / "cgroup", "0::/batch/job_8\n");
  write_file(root / "batch/job_8/memory.max", "max\n");
  write_file(root / "batch/memory.max", "1073741824\n");
  write_file(root / "batch/memory.current", "300000000\n");
  write_file(root / "batch/memory.stat", "anon 200000000\nfile 50000000\n");
  limit = cli::memory_limit(proc, root);
  ASSERT_TRUE(limit.has_value());
  EXPECT_EQ(limit->bytes, 1073741824u);
  EXPECT_EQ(limit->used, 250000000u);
  EXPECT_EQ(limit->source, "the memory cgroup's memory.max");
  // No limit anywhere.
  write_file(root / "batch/memory.max", "max\n");
  EXPECT_FALSE(cli::memory_limit(proc, root).has_value());
}

TEST(MemoryLimit, AFrameThatRanOutOfMemorySaysWhatItNeeds) {
  const ClothGenerator cloth(ClothKind::Curtain, {30, 2, 24.0, 0});
  const Frame frame = cloth.frame(1);
  const SlicingPlan plan = make_diffuse_plan(cloth.topology(), frame, {});
  const std::size_t count = cli::SliceVertexCounter(cloth.topology(), plan).count(frame);
  std::vector<SlicingPlane> planes;
  planes_for_frame(plan, cloth_vertices(cloth.topology()), frame, planes);
  const std::string what = cli::out_of_memory_in_frame(cloth.topology(), frame, plan, 1, 2).what();
  EXPECT_EQ(what.rfind("out of memory computing frame 1, which needs about ", 0), 0u) << what;
  EXPECT_NE(what.find("(" + std::to_string(count) + " slice vertices over " + std::to_string(planes.size()) +
                      " planes, 2 threads)"),
            std::string::npos)
      << what;
}

TEST(MemoryLimit, TheEstimateGrowsWithSliceVerticesAndThreads) {
  EXPECT_EQ(cli::frame_need(1000000, 1, /*address_space=*/false), 450000000u);
  EXPECT_EQ(cli::frame_need(1000000, 1, true), 500000000u);
  EXPECT_EQ(cli::frame_need(1000000, 3, true), 500000000u + 2 * (64u << 20));
  EXPECT_EQ(cli::format_bytes(3435973837u), "3.2 GB");
  EXPECT_EQ(cli::format_bytes(600u << 20), "600 MB");
}

}  // namespace
}  // namespace pleat
