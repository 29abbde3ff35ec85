#include "validate/verify_exclusion.hpp"

#include <CGAL/Interval_nt.h>

#include <algorithm>

namespace snag::validate {

namespace {

using Interval = CGAL::Interval_nt<true>;  // each operation rounds outward itself

struct IVec {
  Interval c[3];
};

IVec operator-(const IVec& p, const IVec& q) {
  return {{p.c[0] - q.c[0], p.c[1] - q.c[1], p.c[2] - q.c[2]}};
}

Interval det(const IVec& a, const IVec& b, const IVec& c) {
  return a.c[0] * (b.c[1] * c.c[2] - b.c[2] * c.c[1]) - a.c[1] * (b.c[0] * c.c[2] - b.c[2] * c.c[0]) +
         a.c[2] * (b.c[0] * c.c[1] - b.c[1] * c.c[0]);
}

// Encloses x_t0 + t (x_t1 - x_t0) for an exact t.
IVec position_at(const Vec3& x_t0, const Vec3& x_t1, double t) {
  const double a[3] = {x_t0.x, x_t0.y, x_t0.z}, b[3] = {x_t1.x, x_t1.y, x_t1.z};
  IVec p;
  for (int k = 0; k < 3; ++k) p.c[k] = Interval(a[k]) + Interval(t) * (Interval(b[k]) - Interval(a[k]));
  return p;
}

struct Box {
  double lo[3], hi[3];
};

// Box of the corners first..last at both slice ends (outer bounds of their enclosures).
Box slice_box(const IVec* start, const IVec* end, int first, int last) {
  Box box;
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = std::min(start[first].c[k].inf(), end[first].c[k].inf());
    box.hi[k] = std::max(start[first].c[k].sup(), end[first].c[k].sup());
    for (int i = first + 1; i <= last; ++i) {
      box.lo[k] = std::min({box.lo[k], start[i].c[k].inf(), end[i].c[k].inf()});
      box.hi[k] = std::max({box.hi[k], start[i].c[k].sup(), end[i].c[k].sup()});
    }
  }
  return box;
}

bool boxes_apart(const Box& a, const Box& b, double d) {
  for (int k = 0; k < 3; ++k) {
    if ((Interval(b.lo[k]) - Interval(a.hi[k])).inf() > d) return true;
    if ((Interval(a.lo[k]) - Interval(b.hi[k])).inf() > d) return true;
  }
  return false;
}

// The three vectors of the coplanarity determinant from the four corners.
void coplanarity_vectors(const IVec* p, bool edge_edge, IVec& x, IVec& y, IVec& z) {
  if (edge_edge) {
    x = p[1] - p[0];  // ea1 - ea0
    y = p[3] - p[2];  // eb1 - eb0
    z = p[2] - p[0];  // eb0 - ea0
  } else {
    x = p[2] - p[1];  // b - a
    y = p[3] - p[1];  // c - a
    z = p[0] - p[1];  // p - a
  }
}

bool never_coplanar_on_slice(const IVec* start, const IVec* end, bool edge_edge) {
  IVec x[2], y[2], z[2];
  coplanarity_vectors(start, edge_edge, x[0], y[0], z[0]);
  coplanarity_vectors(end, edge_edge, x[1], y[1], z[1]);
  // Sums of det(X_i, Y_j, Z_k) by m = i + j + k; the factors 1 / C(3, m) are
  // positive and do not change signs.
  Interval sums[4] = {Interval(0), Interval(0), Interval(0), Interval(0)};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) sums[i + j + k] += det(x[i], y[j], z[k]);
  bool all_positive = true, all_negative = true;
  for (const Interval& s : sums) {
    all_positive = all_positive && s.inf() > 0;
    all_negative = all_negative && s.sup() < 0;
  }
  return all_positive || all_negative;
}

}  // namespace

bool certainly_apart(const std::array<Vec3, 8>& points, bool edge_edge, double thickness) {
  IVec start[4], end[4];
  for (int i = 0; i < 4; ++i) start[i] = position_at(points[i], points[i + 4], 0.0);
  for (int slice = 0; slice < kExclusionSlices; ++slice) {
    const double tb = static_cast<double>(slice + 1) / kExclusionSlices;  // exact: a power-of-two denominator
    for (int i = 0; i < 4; ++i) end[i] = position_at(points[i], points[i + 4], tb);
    // VF: corner 0 is the vertex, 1..3 the face; EE: 0..1 and 2..3 the edges.
    const Box a = edge_edge ? slice_box(start, end, 0, 1) : slice_box(start, end, 0, 0);
    const Box b = edge_edge ? slice_box(start, end, 2, 3) : slice_box(start, end, 1, 3);
    const bool excluded =
        boxes_apart(a, b, thickness) || (thickness == 0 && never_coplanar_on_slice(start, end, edge_edge));
    if (!excluded) return false;
    std::copy(std::begin(end), std::end(end), std::begin(start));
  }
  return true;
}

}  // namespace snag::validate
