#include "cli/progress.hpp"

#include <algorithm>
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
  const std::lock_guard lock(m_mutex);
  m_done = done;
  m_within = 0.0;
  m_within_what.clear();
  m_detail = detail;
  update(detail);
}

void Progress::set_within(double fraction, const std::string& what) {
  const std::lock_guard lock(m_mutex);
  if (m_done >= m_total) return;
  m_within = std::clamp(fraction, 0.0, 1.0);
  m_within_what = what;
  update(m_detail);
}

void Progress::update(const std::string& detail) {
  const double done = double(m_done) + m_within;
  if (m_mode == ProgressMode::None || m_finished || done <= 0.0) return;
  const auto now = std::chrono::steady_clock::now();
  const bool last = m_done >= m_total;
  if (m_mode == ProgressMode::Bar) {
    if (!last && m_printed && now - m_last < std::chrono::milliseconds(200)) return;
  } else {
    if (m_printed && done == m_printed_done) return;
    const double since = m_total > 0 ? 100.0 * (done - m_printed_done) / double(m_total) : 100.0;
    if (!last && since < 5.0 && now - m_last < std::chrono::seconds(10)) return;
  }
  m_last = now;
  print(detail);
}

void Progress::print(const std::string& detail) {
  const double done = double(m_done) + m_within;
  const double elapsed = std::chrono::duration<double>(m_last - m_start).count();
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  const double left = rate > 0 && double(m_total) > done ? (double(m_total) - done) / rate : 0.0;
  const double percent = m_total > 0 ? 100.0 * done / double(m_total) : 100.0;
  const std::string within = m_within_what.empty() ? "" : "  " + m_within_what;
  if (m_mode == ProgressMode::Bar)
    std::fprintf(stderr, "\r%s %zu/%zu %s  %.*f/s  %.0f s left%s%s   ", m_what.c_str(), m_done, m_total,
                 m_unit.c_str(), rate < 1 ? 2 : 1, rate, left, detail.c_str(), within.c_str());
  else
    std::fprintf(stderr, "pleat: %s %zu/%zu %s %.1f%% %.*f %s/s eta %.0f s%s%s\n", m_what.c_str(), m_done,
                 m_total, m_unit.c_str(), percent, rate < 1 ? 2 : 1, rate, m_unit.c_str(), left,
                 detail.c_str(), within.c_str());
  std::fflush(stderr);
  m_printed = true;
  m_printed_done = done;
}

void Progress::finish() {
  const std::lock_guard lock(m_mutex);
  if (m_finished) return;
  m_within = 0.0;
  m_within_what.clear();
  if (m_mode == ProgressMode::Lines && m_done > 0 && (!m_printed || m_printed_done != double(m_done))) {
    m_last = std::chrono::steady_clock::now();
    print(m_detail);
  }
  if (m_mode == ProgressMode::Bar && m_printed) std::fprintf(stderr, "\n");
  m_finished = true;
}

FrameTicker::FrameTicker(std::function<void()> tick) : m_tick(std::move(tick)) {
  m_thread = std::thread([this] {
    std::unique_lock lock(m_mutex);
    while (!m_wake.wait_for(lock, std::chrono::seconds(1), [this] { return m_stop; })) {
      lock.unlock();
      m_tick();
      lock.lock();
    }
  });
}

FrameTicker::~FrameTicker() {
  {
    const std::lock_guard lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_one();
  m_thread.join();
}

}  // namespace pleat::cli
