// Test meshes built in code: a square grid of n x n vertices, two triangles
// per cell (vertex i * n + j at row i, column j).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "libcd/scene/object.hpp"

namespace snag::test {

inline Object grid_object(const std::string& name, Index n) {
  std::vector<Triangle> triangles;
  for (Index i = 0; i + 1 < n; ++i) {
    for (Index j = 0; j + 1 < n; ++j) {
      const Index v = i * n + j;
      triangles.push_back({v, v + 1, v + n});
      triangles.push_back({v + 1, v + n + 1, v + n});
    }
  }
  return make_object(name, n * n, std::move(triangles));
}

}  // namespace snag::test
