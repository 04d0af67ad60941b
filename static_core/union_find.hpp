// Union-find over indices in a vector (parent[i] == i at a root), for the few places that group items:
// the 3D assembly's wedges, the boundary components of a region with holes.
#pragma once

#include <vector>

namespace pleat {

/// The root of i's set, halving the path on the way (parent[i] must be set for every index on it).
inline int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace pleat
