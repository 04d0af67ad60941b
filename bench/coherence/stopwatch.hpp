// Wall and process-CPU time of one step (the benchmark reports both: wall time is what a user waits for, CPU
// time at one thread is the one-core cost, robust to other jobs on a shared machine).
#pragma once

#include <time.h>

#include <chrono>

namespace pleat::bench {

class Stopwatch {
 public:
  Stopwatch() : m_wall(std::chrono::steady_clock::now()), m_cpu(cpu_ms()) {}
  double wall_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_wall).count();
  }
  double process_cpu_ms() const { return cpu_ms() - m_cpu; }

 private:
  static double cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
  }
  std::chrono::steady_clock::time_point m_wall;
  double m_cpu;
};

}  // namespace pleat::bench
