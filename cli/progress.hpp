// Progress of long work on stderr, as --progress says (cli/global_options.hpp): a bar redrawn in place
// (done/total, rate, time left), or for logs one parseable line when another 5% is done or 10 s have passed
// since the last line (and one at the end):
//   pleat: visibility 37/120 frames 30.8% 2.1 frames/s eta 40 s
// Within a long frame, the part of it done counts too (set_within; the visibility engines' slices and
// vertices, reported by a FrameTicker thread about once a second):
//   pleat: visibility 0/1 frames 37.0% 0.01 frames/s eta 44 s  frame 0: 520/1404 slices
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "cli/global_options.hpp"

namespace pleat::cli {

class Progress {
 public:
  /// `what` names the work (the subcommand), `unit` what is counted.
  Progress(std::string what, std::size_t total, std::string unit = "frames",
           ProgressMode mode = progress_mode(isatty(STDERR_FILENO) != 0));
  ~Progress() { finish(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::size_t n = 1) { set(m_done + n); }
  /// `done` of the total are done; `detail` is appended to the bar or line (e.g. per-rank counts). Clears
  /// what set_within() said.
  void set(std::size_t done, const std::string& detail = "");
  /// `fraction` (0 to 1) of the next unit is done too, `what` saying how far ("frame 3: 520/1404 slices").
  void set_within(double fraction, const std::string& what);
  /// Ends the bar's line, or prints the last line if it was not printed. Called once (the destructor calls
  /// it).
  void finish();
  // Every member function may be called from any thread (one lock).

 private:
  void update(const std::string& detail);
  void print(const std::string& detail);

  std::string m_what;
  std::string m_unit;
  std::size_t m_total;
  ProgressMode m_mode;
  std::mutex m_mutex;
  std::size_t m_done = 0;
  double m_within = 0.0;  // of the next unit
  std::string m_within_what;
  double m_printed_done = 0.0;  // done (with the part within) at the last line or bar drawn
  bool m_printed = false;
  bool m_finished = false;
  std::string m_detail;
  std::chrono::steady_clock::time_point m_start;
  std::chrono::steady_clock::time_point m_last{};
};

/// A thread that calls `tick` about once a second until destroyed (for progress within long frames: it reads
/// the engine's counters, static_core/visibility.hpp's FrameProgress, and calls Progress::set_within).
class FrameTicker {
 public:
  explicit FrameTicker(std::function<void()> tick);
  ~FrameTicker();
  FrameTicker(const FrameTicker&) = delete;
  FrameTicker& operator=(const FrameTicker&) = delete;

 private:
  std::function<void()> m_tick;
  std::mutex m_mutex;
  std::condition_variable m_wake;
  bool m_stop = false;
  std::thread m_thread;
};

}  // namespace pleat::cli
