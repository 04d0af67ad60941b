#include "cli/run_chunks.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numeric>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include "cli/global_options.hpp"
#include "cli/progress.hpp"
#include "cli/world.hpp"
#include "support/byte_stream.hpp"

namespace pleat::cli {

namespace {

constexpr int kFrameTag = 1;     // one frame's result: header (chunk, frame) + payload
constexpr int kProgressTag = 2;  // a rank's count of frames done

// Whether this rank's stderr is a terminal, or under mpirun its launcher's: for --progress auto.
bool launcher_terminal() {
  if (isatty(STDERR_FILENO) != 0) return true;
  if (!World::launched()) return false;
  // Under mpirun a rank's stderr is a pipe to its launcher (mpirun itself on its node): show progress when
  // the launcher's stderr is a terminal.
  char target[256] = {};
  const std::string link = "/proc/" + std::to_string(getppid()) + "/fd/2";
  const ssize_t n = ::readlink(link.c_str(), target, sizeof target - 1);
  const std::string tty(target, n > 0 ? std::size_t(n) : 0);
  return tty.rfind("/dev/pts/", 0) == 0 || tty.rfind("/dev/tty", 0) == 0;
}

// Rank 0's view of the progress: frames done per rank, shown as one bar or line (cli/progress.hpp) with the
// counts of each rank.
class RankProgress {
 public:
  // Collective: rank 0 decides whether progress is shown, and every rank learns it (the other ranks then
  // send rank 0 one message per frame, which it receives to the last).
  RankProgress(std::string what, const ChunkJob& job)
      : m_total(std::size_t(World::size()), 0), m_done(std::size_t(World::size()), 0) {
    const ProgressMode mode = World::root() ? progress_mode(launcher_terminal()) : ProgressMode::None;
    std::string enabled(1, mode != ProgressMode::None ? '1' : '0');
    World::broadcast(enabled, 0);
    m_enabled = enabled == "1";
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
    if (!m_enabled || !World::distributed()) return;
    for (int r = 1; r < World::size(); ++r) {
      while (m_done[std::size_t(r)] < m_total[std::size_t(r)]) {
        const std::optional<World::Message> message = World::receive(r, kProgressTag, wait);
        if (!message) break;
        m_done[std::size_t(r)] = ByteReader(message->bytes).get<std::uint64_t>();
      }
    }
    print();
  }
  void finish() { m_line->finish(); }
  /// The part of the frame `work` is at, from any thread. Slices weigh 2/3 of a frame, the assembly of
  /// vertices 1/3 (as on the generated 90k-vertex curtain, one thread).
  void within(const FrameWork& work) {
    const std::int64_t frame = work.frame.load();
    const std::size_t planes = work.counters.planes.load(std::memory_order_relaxed);
    if (!m_enabled || frame < 0 || planes == 0 || work.vertices == 0) return;
    const std::size_t slices = std::min(work.counters.slices.load(std::memory_order_relaxed), planes);
    const std::size_t vertices =
        std::min(work.counters.vertices.load(std::memory_order_relaxed), work.vertices);
    std::string what = "frame " + std::to_string(frame) + ": " + std::to_string(slices) + "/" +
                       std::to_string(planes) + " slices";
    if (vertices > 0)
      what += ", " + std::to_string(vertices) + "/" + std::to_string(work.vertices) + " vertices";
    m_line->set_within(
        (2.0 * double(slices) / double(planes) + double(vertices) / double(work.vertices)) / 3.0, what);
  }

 private:
  void print() {
    if (!m_enabled) return;
    std::string ranks;
    if (World::distributed())
      for (int r = 0; r < World::size(); ++r)
        ranks += "  r" + std::to_string(r) + " " + std::to_string(m_done[std::size_t(r)]) + "/" +
                 std::to_string(m_total[std::size_t(r)]);
    m_line->set(std::accumulate(m_done.begin(), m_done.end(), std::size_t(0)), ranks);
  }
  bool m_enabled;
  std::vector<std::size_t> m_total, m_done;
  std::optional<Progress> m_line;
};

// A rank other than 0: computes its chunks; every frame goes to rank 0 as soon as it is done.
void run_own_chunks(const ChunkJob& job, const ComputeChunk& compute, const RankProgress& progress) {
  std::uint64_t done = 0;
  for (std::size_t c = 0; c + 1 < job.bounds.size(); ++c) {
    if (job.owner[c] != World::rank()) continue;
    compute(job.bounds[c], job.bounds[c + 1], [&](std::size_t frame, std::string bytes) {
      std::string message = ByteWriter().put<std::uint64_t>(c).put<std::uint64_t>(frame).take();
      message += bytes;
      World::send(0, kFrameTag, std::move(message));
      ++done;
      if (progress.enabled()) World::send(0, kProgressTag, ByteWriter().put(done).take());
      maybe_kill_for_test();
    });
  }
  World::wait_sends();
}

}  // namespace

void maybe_kill_for_test() {
  static const char* target = std::getenv("PLEAT_TEST_KILL_RANK");
  if (target && std::atoi(target) == World::rank() && World::distributed()) std::raise(SIGKILL);
}

void run_chunks(const ChunkJob& job, const std::string& what, const ComputeChunk& compute,
                const ConsumeFrame& consume, const FrameWork* work) {
  const std::size_t count = job.bounds.size() - 1;
  RankProgress progress(what, job);
  if (!World::root()) {
    run_own_chunks(job, compute, progress);
    return;
  }
  std::optional<FrameTicker> ticker;  // progress within rank 0's own frames
  if (work && progress.enabled()) try {
      ticker.emplace([&progress, work] { progress.within(*work); });
    } catch (const std::system_error&) {  // no thread to spare (a memory limit): frames alone are shown
    }

  // Rank 0: frames of other ranks arrive in order per rank; hold each chunk until it is its turn. With a
  // checkpoint, finished chunks of other ranks are saved as they arrive (drained between rank 0's own
  // frames), so that a rank lost later does not lose them; without one, they wait in their senders' memory.
  std::map<std::size_t, std::vector<std::pair<std::size_t, std::string>>> received;
  auto receive_one = [&](bool wait) {
    const std::optional<World::Message> message = World::receive(World::kAnyRank, kFrameTag, wait);
    if (!message) return false;
    ByteReader header(message->bytes);
    const auto c = header.get<std::uint64_t>();
    const auto frame = header.get<std::uint64_t>();
    auto& frames = received[c];
    frames.emplace_back(frame, std::string(header.rest()));
    if (job.checkpoint && frames.size() == job.bounds[c + 1] - job.bounds[c]) {
      ChunkFile file(*job.checkpoint, job.bounds[c], job.bounds[c + 1], job.chunk_keys[c]);
      for (const auto& [f, bytes] : frames) file.add(f, bytes);
      file.commit();
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
        if (job.checkpoint && World::distributed())
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
      job.checkpoint->read(first, last, job.chunk_keys[c], consume);
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
  ticker.reset();
  progress.finish();
}

}  // namespace pleat::cli
