#include "cli/progress.hpp"

#include <cstdio>

namespace pleat::cli {

Progress::Progress(std::string what, std::size_t total, std::string unit, ProgressMode mode)
    : m_what(std::move(what)),
      m_unit(std::move(unit)),
      m_total(total),
      m_mode(mode),
      m_start(std::chrono::steady_clock::now()),
      m_last(m_start) {}

void Progress::set(std::size_t done, const std::string& detail) {
  m_done = done;
  m_detail = detail;
  if (m_mode == ProgressMode::None || m_finished || done == 0) return;
  const auto now = std::chrono::steady_clock::now();
  const bool last = done >= m_total;
  if (m_mode == ProgressMode::Bar) {
    if (!last && m_printed && now - m_last < std::chrono::milliseconds(200)) return;
  } else {
    if (m_printed && done == m_printed_done) return;
    const double since = m_total > 0 ? 100.0 * double(done - m_printed_done) / double(m_total) : 100.0;
    if (!last && since < 5.0 && now - m_last < std::chrono::seconds(10)) return;
  }
  m_last = now;
  print(detail);
}

void Progress::print(const std::string& detail) {
  const double elapsed = std::chrono::duration<double>(m_last - m_start).count();
  const double rate = elapsed > 0 ? double(m_done) / elapsed : 0.0;
  const double left = rate > 0 && m_total > m_done ? double(m_total - m_done) / rate : 0.0;
  const double percent = m_total > 0 ? 100.0 * double(m_done) / double(m_total) : 100.0;
  if (m_mode == ProgressMode::Bar)
    std::fprintf(stderr, "\r%s %zu/%zu %s  %.*f/s  %.0f s left%s   ", m_what.c_str(), m_done, m_total,
                 m_unit.c_str(), rate < 1 ? 2 : 1, rate, left, detail.c_str());
  else
    std::fprintf(stderr, "pleat: %s %zu/%zu %s %.1f%% %.*f %s/s eta %.0f s%s\n", m_what.c_str(), m_done,
                 m_total, m_unit.c_str(), percent, rate < 1 ? 2 : 1, rate, m_unit.c_str(), left,
                 detail.c_str());
  std::fflush(stderr);
  m_printed = true;
  m_printed_done = m_done;
}

void Progress::finish() {
  if (m_finished) return;
  if (m_mode == ProgressMode::Lines && m_done > 0 && (!m_printed || m_printed_done != m_done)) {
    m_last = std::chrono::steady_clock::now();
    print(m_detail);
  }
  if (m_mode == ProgressMode::Bar && m_printed) std::fprintf(stderr, "\n");
  m_finished = true;
}

}  // namespace pleat::cli
