// The in-memory model: welding over all frames, removed faces, frame rate, OBJ sequences (pattern and
// directory), load_sequence dispatch, the atomic writer and the visibility CSV.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>

#include "sim_io/load_sequence.hpp"
#include "sim_io/mesh_report.hpp"
#include "sim_io/mesh_sequence.hpp"
#include "sim_io/obj_format.hpp"
#include "sim_io/obj_sequence.hpp"
#include "sim_io/visibility_csv.hpp"
#include "sim_io_fixtures.hpp"
#include "support/atomic_file.hpp"
#include "support/input_error.hpp"
#include "test_support.hpp"

namespace pleat {
namespace {

using test::TempDir;

// Two triangles sharing an edge, exported with the shared edge's vertices duplicated (4 -> 6 inputs).
MeshSequence split_pair(std::vector<std::vector<glm::dvec3>> frames) {
  std::vector<double> times;
  for (std::size_t i = 0; i < frames.size(); ++i) times.push_back(double(i) * 0.5);
  return MeshSequence("split", {{0, 1, 2}, {3, 4, 5}}, 6, make_memory_source(std::move(frames), times));
}

TEST(SimIoSequence, WeldsPositionsCoincidentInEveryFrame) {
  const std::vector<glm::dvec3> f0 = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {-0.0, 1, 0}};
  std::vector<glm::dvec3> f1 = f0;
  for (auto& p : f1) p.z += 1.0;
  const MeshSequence s = split_pair({f0, f1});
  EXPECT_EQ(s.topology().num_vertices, 4u);
  EXPECT_EQ(s.welded_duplicates(), 2u);
  EXPECT_EQ(s.welded_of_input(), (std::vector<Index>{0, 1, 2, 1, 3, 2}));  // -0 == +0
  EXPECT_EQ(s.topology().triangles, (std::vector<Triangle>{{0, 1, 2}, {1, 3, 2}}));
  EXPECT_EQ(s.frame(1).positions[3], glm::dvec3(1, 1, 1));
  EXPECT_EQ(s.input_positions(1).size(), 6u);
  EXPECT_DOUBLE_EQ(s.frame_rate(), 2.0);
  EXPECT_DOUBLE_EQ(s.duration(), 0.5);
}

TEST(SimIoSequence, DoesNotWeldWhatSeparatesInALaterFrame) {
  const std::vector<glm::dvec3> f0 = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<glm::dvec3> f1 = f0;
  f1[3].y = -0.25;  // the second triangle's copy of (1,0,0) tears away
  const MeshSequence s = split_pair({f0, f1});
  EXPECT_EQ(s.topology().num_vertices, 5u);
  EXPECT_EQ(s.welded_duplicates(), 1u);
}

TEST(SimIoSequence, CollapsedAndRepeatedFacesAreRemovedAndCounted) {
  std::vector<std::vector<glm::dvec3>> frames = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}}};
  const MeshSequence s("x", {{0, 1, 2}, {0, 3, 1}, {2, 1, 0}, {1, 2, 0}}, 4,
                       make_memory_source(frames, {0.0}));
  EXPECT_EQ(s.topology().triangles.size(), 1u);
  EXPECT_EQ(s.removed_faces(), 3u);
  EXPECT_EQ(s.frame_rate(), 0.0);
}

TEST(SimIoSequence, FrameErrorsNameTheFrame) {
  const auto bad = [](std::vector<std::vector<glm::dvec3>> frames, std::vector<double> times) {
    try {
      MeshSequence("seq", {{0, 1, 2}}, 3, make_memory_source(std::move(frames), std::move(times)));
    } catch (const InputError& e) {
      return e.place();
    }
    return std::string("no error");
  };
  const std::vector<glm::dvec3> ok = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(bad({ok, {{0, 0, 0}}}, {0, 1}), "frame 1");
  EXPECT_EQ(bad({ok, ok}, {0, 0}), "frame 1");
  EXPECT_EQ(bad({ok, {{0, 0, 0}, {1, std::numeric_limits<double>::quiet_NaN(), 0}, {0, 1, 0}}}, {0, 1}),
            "frame 1, vertex 1");
  EXPECT_THROW(MeshSequence("seq", {{0, 1, 5}}, 3, make_memory_source({ok}, {0.0})), InputError);
  EXPECT_THROW(MeshSequence("seq", {}, 3, make_memory_source({ok}, {0.0})), InputError);
}

TEST(SimIoSequence, TopologyCounts) {
  // Golden quad + pentagon: 7 vertices, 5 triangles, 11 edges of which 7 on the single boundary loop.
  const MeshSequence s = load_sequence(test::source_dir() / "tests/golden/quad_pentagon.obj");
  const TopologyCounts c = count_topology(s.topology());
  EXPECT_EQ(c.edges, 11u);
  EXPECT_EQ(c.boundary_edges, 7u);
  EXPECT_EQ(c.boundary_loops, 1u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
  EXPECT_EQ(c.inconsistent_edges, 0u);
  EXPECT_EQ(c.components, 1u);
  // Three triangles on one edge, one flipped neighbour, an isolated vertex.
  const MeshTopology fan{.num_vertices = 6, .triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}};
  const TopologyCounts f = count_topology(fan);
  EXPECT_EQ(f.non_manifold_edges, 1u);
  EXPECT_EQ(f.isolated_vertices, 1u);
  const MeshTopology flipped{.num_vertices = 4, .triangles = {{0, 1, 2}, {0, 1, 3}}};
  EXPECT_EQ(count_topology(flipped).inconsistent_edges, 1u);
}

TEST(SimIoSequence, DegenerateFacesAreCountedExactly) {
  const MeshTopology t{.num_vertices = 5, .triangles = {{0, 1, 2}, {0, 1, 3}, {0, 0, 4}}};
  Frame f;
  f.positions = {{0, 0, 0}, {1, 1, 1}, {0.1, 0.1, 0.1}, {0, 1, 0}, {3, 3, 3}};
  EXPECT_EQ(count_degenerate_faces(t, f), 2u);  // collinear, and a repeated corner
  Frame g;
  g.positions = {{0, 0, 0}, {1, 1, 1}, {0.1, 0.1, 0.1 + 1e-18}, {0, 1, 0}, {3, 3, 3}};
  EXPECT_EQ(count_degenerate_faces(t, g), 2u);  // 0.1 + 1e-18 == 0.1 in doubles
  g.positions[2].z = std::nextafter(0.1, 1.0);
  EXPECT_EQ(count_degenerate_faces(t, g), 1u);  // one ulp off the line: not degenerate
}

TEST(SimIoSequence, ObjSequenceByPatternAndDirectory) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(3, 2, 12);
  std::filesystem::create_directories(dir / "frames");
  write_obj_sequence((dir / "frames/f_%04d.obj").string(), sheet, 1);
  test::write_bytes(dir / "frames/readme.txt", "not a frame");
  const MeshSequence by_pattern = load_sequence((dir / "frames/f_%04d.obj").string());
  EXPECT_EQ(by_pattern.num_frames(), 12u);
  EXPECT_EQ(test::all_positions(by_pattern), test::all_positions(sheet));
  EXPECT_DOUBLE_EQ(by_pattern.frame_rate(), 24.0);
  const MeshSequence by_directory = load_sequence(dir / "frames");
  EXPECT_EQ(test::all_positions(by_directory), test::all_positions(sheet));

  // Natural order: f_2 before f_10 without zero padding.
  std::filesystem::create_directories(dir / "plain");
  write_obj_sequence((dir / "plain/f_%d.obj").string(), sheet, 0);
  EXPECT_EQ(test::all_positions(load_sequence(dir / "plain")), test::all_positions(sheet));
  EXPECT_EQ(test::all_positions(load_sequence((dir / "plain/f_%d.obj").string())),
            test::all_positions(sheet));
}

TEST(SimIoSequence, ObjSequenceErrors) {
  TempDir dir;
  const MeshSequence sheet = test::folding_sheet(2, 2, 4);
  write_obj_sequence((dir / "f_%02d.obj").string(), sheet, 0);
  std::filesystem::remove(dir / "f_02.obj");
  try {
    load_sequence((dir / "f_%02d.obj").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "f_02.obj").string());
  }
  // A frame with different connectivity.
  write_obj_sequence((dir / "f_%02d.obj").string(), sheet, 0);
  MeshTopology other = sheet.topology();
  std::swap(other.triangles[0], other.triangles[1]);
  write_obj(dir / "f_03.obj", other, sheet.frame(3).positions);
  try {
    load_sequence((dir / "f_%02d.obj").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "f_03.obj").string());
    EXPECT_EQ(e.place(), "frame 3");
    EXPECT_NE(std::string(e.what()).find("connectivity"), std::string::npos);
  }
  EXPECT_THROW(load_sequence((dir / "g_%02d.obj").string()), InputError);  // nothing matches
  EXPECT_THROW(load_sequence((dir / "f_%02d_%d.obj").string()), InputError);
  EXPECT_THROW(load_sequence(dir / "x.stl"), InputError);
  EXPECT_THROW(load_sequence(dir / "f_00.obj", dir / "f_01.obj"), InputError);  // not a cache format
}

TEST(SimIoSequence, FramePatternRecognition) {
  EXPECT_TRUE(is_frame_pattern("a/f_%04d.obj"));
  EXPECT_TRUE(is_frame_pattern("f%d.obj"));
  EXPECT_FALSE(is_frame_pattern("f_100%%.obj"));
  EXPECT_FALSE(is_frame_pattern("f_%s.obj"));
  EXPECT_FALSE(is_frame_pattern("plain.obj"));
}

TEST(SimIoAtomicFile, FailedWriteLeavesNoFile) {
  TempDir dir;
  EXPECT_THROW(write_file_atomically(dir / "out.csv",
                                     [](std::ostream& out) {
                                       out << "half of the content";
                                       throw std::runtime_error("computation failed");
                                     }),
               std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // neither the output nor a temporary file
}

TEST(SimIoAtomicFile, FailedWriteKeepsThePreviousFile) {
  TempDir dir;
  write_file_atomically(dir / "out.txt", std::string("old"));
  EXPECT_THROW(write_file_atomically(dir / "out.txt",
                                     [](std::ostream& out) {
                                       out << "new but broken";
                                       throw std::runtime_error("boom");
                                     }),
               std::runtime_error);
  EXPECT_EQ(test::slurp(dir / "out.txt"), "old");
  EXPECT_EQ(
      std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()),
      1);
}

TEST(SimIoAtomicFile, UnfinishedStreamingWritersLeaveNothing) {
  TempDir dir;
  {
    VisibilityCsvWriter csv(dir / "v.csv", {0, 1});
    csv.add_frame(0, 0, {0.5, 0.5}, {1.0, 1.0});
  }  // destroyed without commit
  {
    AtomicFile file(dir / "x.bin");
    file.stream() << "partial";
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  EXPECT_THROW(
      write_obj(dir / "missing_dir/a.obj", MeshTopology{3, {{0, 1, 2}}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}),
      std::runtime_error);
}

// The names in `dir` other than `keep`: what a write left behind (temporaries are hidden .NAME.tmp.*).
std::vector<std::string> other_names(const std::filesystem::path& dir, const std::set<std::string>& keep) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (!keep.count(entry.path().filename().string())) names.push_back(entry.path().filename().string());
  return names;
}

TEST(SimIoAtomicFile, WritesThroughSymbolicLinks) {
  // link.txt -> ../data/chain.txt -> file.txt: each link read from its own directory; both links stay
  // links, the file they lead to is replaced, and the temporary lived beside it.
  TempDir dir;
  std::filesystem::create_directories(dir / "out");
  std::filesystem::create_directories(dir / "data");
  write_file_atomically(dir / "data/file.txt", std::string("old"));
  std::filesystem::create_symlink("file.txt", dir / "data/chain.txt");
  std::filesystem::create_symlink("../data/chain.txt", dir / "out/link.txt");
  EXPECT_EQ(resolve_output_target(dir / "out/link.txt"), dir / "out/../data/file.txt");
  write_file_atomically(dir / "out/link.txt", std::string("new"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "out/link.txt"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "data/chain.txt"));
  EXPECT_EQ(test::slurp(dir / "data/file.txt"), "new");
  EXPECT_TRUE(other_names(dir / "out", {"link.txt"}).empty());
  EXPECT_TRUE(other_names(dir / "data", {"file.txt", "chain.txt"}).empty());

  // A dangling link names the file to create.
  std::filesystem::create_symlink("fresh.txt", dir / "out/dangling.txt");
  write_file_atomically(dir / "out/dangling.txt", std::string("created"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "out/dangling.txt"));
  EXPECT_EQ(test::slurp(dir / "out/fresh.txt"), "created");
}

TEST(SimIoAtomicFile, RefusesWhatIsNotARegularFile) {
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);
  std::filesystem::create_directories(dir / "directory");
  std::filesystem::create_symlink("fifo", dir / "link_to_fifo");
  std::filesystem::create_symlink("loop_b", dir / "loop_a");
  std::filesystem::create_symlink("loop_a", dir / "loop_b");
  const std::pair<std::filesystem::path, std::string> refused[] = {
      {dir / "fifo", "(a FIFO)"},
      {dir / "link_to_fifo", "(a FIFO)"},
      {dir / "directory", "(a directory)"},
      {"/dev/null", "(a character device)"},
      {dir / "loop_a", "too many levels of symbolic links"}};
  for (const auto& [path, why] : refused) {
    SCOPED_TRACE(path.string());
    try {
      AtomicFile file(path);
      ADD_FAILURE() << "not refused";
    } catch (const OutputRefused& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
    EXPECT_THROW(resolve_output_target(path), OutputRefused);
  }
  EXPECT_TRUE(std::filesystem::is_fifo(dir / "fifo"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "link_to_fifo"));
  EXPECT_TRUE(std::filesystem::is_directory(dir / "directory"));
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
  EXPECT_TRUE(other_names(dir.path(), {"fifo", "directory", "link_to_fifo", "loop_a", "loop_b"}).empty());
}

TEST(SimIoAtomicFile, TargetTurnedIntoSomethingElseIsNotReplaced) {
  // Checked again at commit: a directory put where the output goes while it was computed stays.
  TempDir dir;
  AtomicFile file(dir / "out.txt");
  file.stream() << "content";
  std::filesystem::create_directories(dir / "out.txt");
  EXPECT_THROW(file.commit(), OutputRefused);
  EXPECT_TRUE(std::filesystem::is_directory(dir / "out.txt"));
}

TEST(SimIoAtomicFile, DashStreamsToStandardOutput) {
  // Standard output redirected to a file for the test: "-" writes there, and creates no file named "-".
  TempDir dir;
  const std::filesystem::path captured = dir / "stdout.txt";
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO);
  const int fd = ::open(captured.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  ::dup2(fd, STDOUT_FILENO);
  ::close(fd);
  const auto previous = std::filesystem::current_path();
  std::filesystem::current_path(dir.path());
  std::string big(200000, 'x');  // more than the stream's buffer
  write_file_atomically(kStandardOutput, "head," + big + ",tail");
  std::filesystem::current_path(previous);
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
  EXPECT_EQ(test::slurp(captured), "head," + big + ",tail");
  EXPECT_FALSE(std::filesystem::exists(dir / "-"));
}

TEST(SimIoVisibilityCsv, RowsPerInputVertexInInputOrderRoundTrip) {
  TempDir dir;
  const std::vector<Index> welded_of_input = {0, 1, 2, 1, 3, 2};
  VisibilityCsvWriter csv(dir / "v.csv", welded_of_input);
  const std::vector<double> front = {0.1, 1.0 / 3.0, 1.0, 0.0}, back = {0.9, 2.0 / 3.0, 1e-300, 0.5};
  csv.add_frame(0, 0, front, back);
  csv.add_frame(7, 7, back, front);
  csv.commit();
  const std::string text = test::slurp(dir / "v.csv");
  EXPECT_EQ(text.substr(0, text.find('\n')), "frame,vertex,front,back,source_frame");
  const auto rows = read_visibility_csv(dir / "v.csv");
  ASSERT_EQ(rows.size(), 12u);
  for (std::size_t r = 0; r < 6; ++r) {
    EXPECT_EQ(rows[r].frame, 0u);
    EXPECT_EQ(rows[r].vertex, r);
    EXPECT_EQ(rows[r].front, front[welded_of_input[r]]);  // exact: shortest round-trip digits
    EXPECT_EQ(rows[r].back, back[welded_of_input[r]]);
    EXPECT_EQ(rows[6 + r].frame, 7u);
    EXPECT_EQ(rows[6 + r].front, back[welded_of_input[r]]);
  }
  test::write_bytes(dir / "bad.csv", "frame,vertex,front,back,source_frame\n0,0,0.5,0.5,0\n0,1,zz,0.5,0\n");
  try {
    read_visibility_csv(dir / "bad.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "line 3");
  }
}

}  // namespace
}  // namespace pleat
