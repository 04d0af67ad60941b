// Progress of long work on stderr, as --progress says (cli/global_options.hpp): a bar redrawn in place
// (done/total, rate, time left), or for logs one parseable line when another 5% is done or 10 s have passed
// since the last line (and one at the end):
//   pleat: visibility 37/120 frames 30.8% 2.1 frames/s eta 40 s
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <string>

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
  /// `done` of the total are done; `detail` is appended to the bar or line (e.g. per-rank counts).
  void set(std::size_t done, const std::string& detail = "");
  /// Ends the bar's line, or prints the last line if it was not printed. Called once (the destructor calls
  /// it).
  void finish();

 private:
  void print(const std::string& detail);

  std::string m_what;
  std::string m_unit;
  std::size_t m_total;
  ProgressMode m_mode;
  std::size_t m_done = 0;
  std::size_t m_printed_done = 0;  // done at the last line or bar drawn
  bool m_printed = false;
  bool m_finished = false;
  std::string m_detail;
  std::chrono::steady_clock::time_point m_start;
  std::chrono::steady_clock::time_point m_last{};
};

}  // namespace pleat::cli
