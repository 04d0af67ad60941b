// Peak-memory windows from /proc/self/status.
#include "bench/coherence/memory_window.hpp"

#include <malloc.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace pleat::bench {

double status_mb(const char* key) {
  std::ifstream in("/proc/self/status");
  const std::size_t n = std::strlen(key);
  for (std::string line; std::getline(in, line);)
    if (line.compare(0, n, key) == 0 && line.size() > n && line[n] == ':')
      return std::strtod(line.c_str() + n + 1, nullptr) / 1024.0;  // kB -> MB
  return NAN;
}

bool start_memory_window(double& rss_before) {
  malloc_trim(0);
  rss_before = status_mb("VmRSS");
  {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    if (!clear) return false;
  }
  return status_mb("VmHWM") <= rss_before + 1.0;
}

}  // namespace pleat::bench
