#include "volume/winding_columns.hpp"

#include <algorithm>
#include <cmath>

namespace snag::volume {

namespace {

struct Point2 {
  double u, v;  // the (y, z) projection
};

bool canonical_before(Point2 p, Point2 q) { return p.u < q.u || (p.u == q.u && p.v < q.v); }

// Twice the signed area of (p, q, r), evaluated with p and q in canonical
// order so that every triangle sharing the edge p–q gets the same number.
double edge_function(Point2 p, Point2 q, Point2 r) {
  if (canonical_before(q, p)) {
    return -((p.u - q.u) * (r.v - q.v) - (p.v - q.v) * (r.u - q.u));
  }
  return (q.u - p.u) * (r.v - p.v) - (q.v - p.v) * (r.u - p.u);
}

// The top-left rule: of the two directions of an edge exactly one owns the
// points on it.
bool owns_edge(Point2 from, Point2 to) {
  const double du = to.u - from.u, dv = to.v - from.v;
  return dv > 0 || (dv == 0 && du < 0);
}

// Crossing of the line through r with triangle (a, b, c), when it has one.
bool cross_triangle(const Vec3& a, const Vec3& b, const Vec3& c, Point2 r, Crossing& out) {
  const Point2 pa{a.y, a.z}, pb{b.y, b.z}, pc{c.y, c.z};
  const double area = edge_function(pa, pb, pc);
  if (area == 0) return false;  // edge-on: its neighbours are crossed instead
  const double flip = area > 0 ? 1 : -1;
  const Point2 corners[3] = {pa, pb, pc};
  double weights[3];
  for (int e = 0; e < 3; ++e) {
    const Point2 from = corners[(e + 1) % 3], to = corners[(e + 2) % 3];
    const double w = flip * edge_function(from, to, r);  // the weight of corner e
    if (w < 0) return false;
    if (w == 0 && !(flip > 0 ? owns_edge(from, to) : owns_edge(to, from))) return false;
    weights[e] = w;
  }
  const double sum = weights[0] + weights[1] + weights[2];
  out.x = (weights[0] * a.x + weights[1] * b.x + weights[2] * c.x) / sum;
  out.sign = area > 0 ? 1 : -1;
  return true;
}

}  // namespace

WindingColumns::WindingColumns(const TriangleMesh& mesh, const Box& box) : mesh_(mesh) {
  orientation_ = signed_volume(mesh) < 0 ? -1 : 1;
  std::vector<std::size_t> listed;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Box b = triangle_box(mesh, t);
    if (b.hi.y >= box.lo.y && b.lo.y <= box.hi.y && b.hi.z >= box.lo.z && b.lo.z <= box.hi.z) listed.push_back(t);
  }
  // About four triangles a cell, at most 512 cells a side.
  y0_ = box.lo.y;
  z0_ = box.lo.z;
  const double su = std::max(box.hi.y - box.lo.y, 1e-300), sv = std::max(box.hi.z - box.lo.z, 1e-300);
  cell_ = std::max({std::sqrt(su * sv * 4 / std::max<double>(listed.size(), 1)), su / 512, sv / 512});
  ny_ = static_cast<std::size_t>(su / cell_) + 1;
  nz_ = static_cast<std::size_t>(sv / cell_) + 1;
  auto clamp_cell = [](double t, std::size_t n) {
    return static_cast<std::size_t>(std::clamp(t, 0.0, static_cast<double>(n - 1)));
  };
  std::vector<std::size_t> counts(ny_ * nz_ + 1, 0);
  auto for_cells = [&](std::size_t t, auto&& visit) {
    const Box b = triangle_box(mesh, t);
    const std::size_t j0 = clamp_cell((b.lo.y - y0_) / cell_, ny_), j1 = clamp_cell((b.hi.y - y0_) / cell_, ny_);
    const std::size_t k0 = clamp_cell((b.lo.z - z0_) / cell_, nz_), k1 = clamp_cell((b.hi.z - z0_) / cell_, nz_);
    for (std::size_t k = k0; k <= k1; ++k)
      for (std::size_t j = j0; j <= j1; ++j) visit(k * ny_ + j);
  };
  for (std::size_t t : listed) for_cells(t, [&](std::size_t c) { ++counts[c + 1]; });
  for (std::size_t c = 1; c < counts.size(); ++c) counts[c] += counts[c - 1];
  cell_start_ = counts;
  cell_triangles_.resize(counts.back());
  for (std::size_t t : listed) for_cells(t, [&](std::size_t c) { cell_triangles_[counts[c]++] = t; });
}

std::size_t WindingColumns::cell_of(double y, double z) const {
  const double j = std::floor((y - y0_) / cell_), k = std::floor((z - z0_) / cell_);
  if (j < 0 || k < 0 || j >= static_cast<double>(ny_) || k >= static_cast<double>(nz_)) return ny_ * nz_;
  return static_cast<std::size_t>(k) * ny_ + static_cast<std::size_t>(j);
}

void WindingColumns::crossings(double y, double z, std::vector<Crossing>& out) const {
  out.clear();
  const std::size_t c = cell_of(y, z);
  if (c >= ny_ * nz_) return;
  const Point2 r{y, z};
  for (std::size_t i = cell_start_[c]; i < cell_start_[c + 1]; ++i) {
    const Triangle& f = mesh_.triangles[cell_triangles_[i]];
    Crossing crossing;
    if (cross_triangle(mesh_.vertices[f[0]], mesh_.vertices[f[1]], mesh_.vertices[f[2]], r, crossing)) {
      crossing.sign *= orientation_;
      out.push_back(crossing);
    }
  }
  std::sort(out.begin(), out.end(), [](const Crossing& a, const Crossing& b) { return a.x < b.x; });
}

int WindingColumns::winding_number(const Vec3& p) const {
  std::vector<Crossing> line;
  crossings(p.y, p.z, line);
  return winding_at(line, p.x);
}

int winding_at(const std::vector<Crossing>& crossings, double x) {
  int winding = 0;
  for (const Crossing& c : crossings) {
    if (c.x > x) winding += c.sign;
  }
  return winding;
}

double length_with_winding(const std::vector<Crossing>& crossings, double x0, double x1, int min_winding) {
  // Walk from +infinity (winding 0) towards -x: between crossings i-1 and i
  // the winding number is the sum of the signs of crossings i and beyond.
  double length = 0;
  int winding = 0;
  double upper = x1;
  for (std::size_t i = crossings.size(); i-- > 0;) {
    const double lower = std::max(crossings[i].x, x0);
    if (winding >= min_winding && upper > lower) length += upper - lower;
    winding += crossings[i].sign;
    upper = std::min(upper, crossings[i].x);
    if (upper <= x0) return length;
  }
  if (winding >= min_winding && upper > x0) length += upper - x0;
  return length;
}

}  // namespace snag::volume
