// Command-line helpers shared by the benchmark programs of bench/ (header-only).
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace pleat::bench {

/// "a,b,,c" -> {"a", "b", "c"}: a comma-separated list, empty items dropped.
inline std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty()) parts.push_back(part);
  return parts;
}

}  // namespace pleat::bench
