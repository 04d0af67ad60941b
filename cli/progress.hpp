// Progress on stderr for long work (done/total, rate, time remaining), only when stderr is a terminal:
// CI logs and pipes stay quiet.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace pleat::cli {

class Progress {
 public:
  Progress(std::string what, std::size_t total)
      : m_what(std::move(what)),
        m_total(total),
        m_enabled(isatty(STDERR_FILENO) != 0),
        m_start(std::chrono::steady_clock::now()) {}
  ~Progress() { finish(); }

  void advance(std::size_t n = 1) {
    m_done += n;
    if (!m_enabled) return;
    const auto now = std::chrono::steady_clock::now();
    if (m_done < m_total && now - m_last < std::chrono::milliseconds(200)) return;
    m_last = now;
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    const double rate = elapsed > 0 ? double(m_done) / elapsed : 0.0;
    const double remaining = rate > 0 ? double(m_total - m_done) / rate : 0.0;
    std::fprintf(stderr, "\r%s %zu/%zu  %.1f/s  %.0f s left   ", m_what.c_str(), m_done, m_total, rate,
                 remaining);
    std::fflush(stderr);
  }

  void finish() {
    if (m_enabled && !m_finished && m_done > 0) std::fprintf(stderr, "\n");
    m_finished = true;
  }

 private:
  std::string m_what;
  std::size_t m_total;
  std::size_t m_done = 0;
  bool m_enabled;
  bool m_finished = false;
  std::chrono::steady_clock::time_point m_start;
  std::chrono::steady_clock::time_point m_last{};
};

}  // namespace pleat::cli
