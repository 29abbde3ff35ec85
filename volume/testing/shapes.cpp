#include "volume/testing/shapes.hpp"

#include <cmath>
#include <algorithm>
#include <map>
#include <utility>

#include "io/mesh_file.hpp"

namespace snag::volume::testing {

TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

TriangleMesh icosphere(const Vec3& centre, double radius, int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  auto normalise = [](Vec3 p) { return p / std::sqrt(squared_norm(p)); };
  for (Vec3& p : unit) p = normalise(p);
  std::vector<Triangle> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<Index, Index>, Index> middle;
    auto mid = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = middle.emplace(key, static_cast<Index>(unit.size()));
      if (added) unit.push_back(normalise(unit[a] + unit[b]));
      return it->second;
    };
    std::vector<Triangle> finer;
    for (const Triangle& f : faces) {
      const Index ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  TriangleMesh m;
  for (const Vec3& p : unit) m.vertices.push_back(centre + radius * p);
  m.triangles = std::move(faces);
  return m;
}

TriangleMesh sheet(const Vec3& centre, double side, int n) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.vertices.push_back(centre + Vec3{side * (static_cast<double>(i) / n - 0.5), side * (static_cast<double>(j) / n - 0.5), 0});
  auto id = [n](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

TriangleMesh turned_about_x(const TriangleMesh& mesh, const Vec3& centre) {
  TriangleMesh m = mesh;
  for (Vec3& p : m.vertices) {
    const Vec3 d = p - centre;
    p = centre + Vec3{d.x, -d.z, d.y};
  }
  return m;
}

TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const Index offset = static_cast<Index>(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (Triangle f : b.triangles) m.triangles.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  return m;
}

TriangleMesh moved(const TriangleMesh& mesh, const Vec3& offset) {
  TriangleMesh m = mesh;
  for (Vec3& p : m.vertices) p = p + offset;
  return m;
}

TriangleMesh read_first_object(const std::string& path) {
  const io::MeshData data = io::read_mesh_file(path);
  TriangleMesh mesh;
  const io::MeshObject& object = data.objects.at(0);
  for (Index v : object.vertices) mesh.vertices.push_back(data.positions[v]);
  mesh.triangles = object.triangles;
  return mesh;
}

}  // namespace snag::volume::testing
