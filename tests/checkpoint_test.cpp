// The checkpoint's chunks carry checksums (cli/checkpoint.hpp): a damaged chunk (a flipped byte, a truncated
// file) is named as damaged and computed again, never used, and the output is the one of a fresh run; tasks
// over other frame ranges that share the directory keep each other's chunks. One process (the runs over
// ranks: distributed_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace pleat {
namespace {

using test::slurp;
namespace fs = std::filesystem;

class Checkpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto made =
        test::run_pleat("generate curtain -o " + (dir / "c.obj").string() + " --resolution 10 --frames 8");
    ASSERT_EQ(made.exit_code, 0) << made.output;
    const auto fresh = test::run_pleat("visibility " + input() + " -o " + (dir / "fresh.csv").string());
    ASSERT_EQ(fresh.exit_code, 0) << fresh.output;
  }
  std::string input() const { return (dir / "c.obj").string() + " --cache " + (dir / "c.pc2").string(); }
  std::string job(const std::string& frames = "") const {
    return "visibility " + input() + " -o " + (dir / "v.csv").string() + " --chunks 3 --checkpoint " +
           (dir / "ck").string() + (frames.empty() ? "" : " --frames " + frames);
  }
  std::vector<fs::path> chunks() const {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir / "ck")) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
  }
  // Runs the job again after `damage` was done to the second chunk: it names that chunk as damaged (and says
  // `why`), computes it again, keeps the others, and writes the fresh run's CSV.
  void expect_recomputed(const std::string& why) {
    const fs::path chunk = chunks()[1];
    fs::remove(dir / "v.csv");
    const auto rerun = test::run_pleat(job());
    ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
    EXPECT_NE(rerun.output.find(chunk.filename().string() + " is damaged ("), std::string::npos)
        << rerun.output;
    EXPECT_NE(rerun.output.find(why), std::string::npos) << rerun.output;
    EXPECT_NE(rerun.output.find("); it is computed again"), std::string::npos) << rerun.output;
    EXPECT_EQ(rerun.output.find("another input, plan or command"), std::string::npos) << rerun.output;
    EXPECT_NE(rerun.output.find("3 chunks over 1 ranks, 2 kept from the checkpoint"), std::string::npos)
        << rerun.output;
    EXPECT_TRUE(slurp(dir / "v.csv") == slurp(dir / "fresh.csv"));
    // And the chunk written again is whole: the next run keeps all three.
    const auto third = test::run_pleat(job());
    EXPECT_NE(third.output.find("3 kept from the checkpoint"), std::string::npos) << third.output;
  }
  void flip(const fs::path& file, std::size_t at) {
    std::string bytes = slurp(file);
    ASSERT_LT(at, bytes.size());
    bytes[at] = char(bytes[at] ^ 0x10);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  }
  test::TempDir dir;
};

TEST_F(Checkpoint, AFlippedByteInAFrameIsDamageNotAResult) {
  ASSERT_EQ(test::run_pleat(job()).exit_code, 0);
  ASSERT_EQ(chunks().size(), 3u);
  flip(chunks()[1], fs::file_size(chunks()[1]) / 2);  // inside a frame's values
  expect_recomputed("the frame's checksum does not match");
}

TEST_F(Checkpoint, AFlippedByteInTheHeaderIsDamage) {
  ASSERT_EQ(test::run_pleat(job()).exit_code, 0);
  flip(chunks()[1], 20);  // the chunk's key
  expect_recomputed("the header's checksum does not match");
}

TEST_F(Checkpoint, ATruncatedChunkIsDamageNotAnotherJob) {
  ASSERT_EQ(test::run_pleat(job()).exit_code, 0);
  const fs::path chunk = chunks()[1];
  fs::resize_file(chunk, fs::file_size(chunk) - 100);
  expect_recomputed("truncated");
}

TEST_F(Checkpoint, ARecordClaimingMoreBytesThanTheFileHoldsIsDamage) {
  // Nothing is allocated for it.
  ASSERT_EQ(test::run_pleat(job()).exit_code, 0);
  {
    std::fstream chunk(chunks()[1], std::ios::binary | std::ios::in | std::ios::out);
    chunk.seekp(36 + 8);  // the header, then the first record's frame number: its byte count
    const std::uint64_t huge = std::uint64_t(1) << 62;
    chunk.write(reinterpret_cast<const char*>(&huge), sizeof huge);
  }
  expect_recomputed("bytes, past the end");
}

TEST_F(Checkpoint, TasksOfOtherFramesSharingTheDirectoryKeepEachOthersChunks) {
  // Two farm tasks, frames 0:4 and 4:8, one checkpoint directory: neither removes the other's chunks, and a
  // rerun of either keeps all of its own.
  const auto first = test::run_pleat(job("0:4"));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const std::vector<fs::path> of_first = chunks();
  ASSERT_EQ(of_first.size(), 3u);
  const auto second = test::run_pleat(job("4:8"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_EQ(second.output.find("removed"), std::string::npos) << second.output;
  EXPECT_EQ(chunks().size(), 6u);
  for (const fs::path& chunk : of_first) EXPECT_TRUE(fs::exists(chunk)) << chunk;
  for (const std::string frames : {"0:4", "4:8"}) {
    const auto rerun = test::run_pleat(job(frames));
    ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
    EXPECT_NE(rerun.output.find("3 kept from the checkpoint"), std::string::npos) << frames << rerun.output;
  }
  // The two halves are the whole shot's rows.
  const auto whole = test::run_pleat("visibility " + input() + " -o " + (dir / "whole.csv").string());
  ASSERT_EQ(whole.exit_code, 0);
  const auto half = test::run_pleat(job("4:8"));
  ASSERT_EQ(half.exit_code, 0);
  const std::string rows = slurp(dir / "v.csv");
  EXPECT_NE(slurp(dir / "whole.csv").find(rows.substr(rows.find('\n') + 1)), std::string::npos);
}

TEST_F(Checkpoint, ChunksOfAnotherPlanAreNotUsed) {
  ASSERT_EQ(test::run_pleat(job()).exit_code, 0);
  const auto replanned = test::run_pleat(job() + " --planes 20");
  ASSERT_EQ(replanned.exit_code, 0) << replanned.output;
  EXPECT_EQ(replanned.output.find("kept from the checkpoint"), std::string::npos) << replanned.output;
}

}  // namespace
}  // namespace pleat
