// The classic cubic CCD, for snag-bench to compare against snag's methods.
//
// X. Provot, "Collision and self-collision handling in cloth model dedicated
// to design garments", Graphics Interface 1997, section 4: under linear
// motion four points can touch only when they are coplanar, which is a cubic
// equation in t,
//   f(t) = (x2(t) - x1(t)) x (x3(t) - x1(t)) . (x4(t) - x1(t)) = 0;
// its roots in [0, 1] are found in increasing order and at each the
// configuration is tested for contact with a tolerance delta: the vertex
// within delta of the triangle (vertex-face), the two segments within delta
// of each other (edge-edge). The first root that passes gives a collision.
//
// Everything is computed in T (float or double), from inputs rounded to T,
// as an implementation of the paper in that precision would. The tolerance is
// delta = sqrt(eps_T) * L, L the largest extent of the 8 points' bounding
// box: the root is only known to about eps_T relative, which moves the points
// by eps_T times their speed, and the distance itself is rounded, so a
// tolerance near eps_T * L would miss contacts that a root landed beside;
// half of T's digits is the usual compromise between missing grazing
// contacts and reporting near misses (sqrt(eps_T) is 3.5e-4 in float and
// 1.5e-8 in double). A pair coplanar for the whole step (f identically 0)
// has every t as a root; it is tested at t = 0, 1/2 and 1, a choice the paper
// leaves open.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "libcd/geometry/vec3.hpp"

namespace snag::bench {

template <typename T>
struct Point3 {
  T x = 0, y = 0, z = 0;
};
template <typename T>
Point3<T> operator+(Point3<T> a, Point3<T> b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <typename T>
Point3<T> operator-(Point3<T> a, Point3<T> b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <typename T>
Point3<T> operator*(T s, Point3<T> a) { return {s * a.x, s * a.y, s * a.z}; }
template <typename T>
T dot(Point3<T> a, Point3<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <typename T>
Point3<T> cross(Point3<T> a, Point3<T> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

namespace cubic_detail {

template <typename T>
T clamp01(T x) { return std::min(T(1), std::max(T(0), x)); }

/// Squared distance from p to the closed triangle (a, b, c) (Ericson,
/// "Real-Time Collision Detection", 5.1.5), degenerate triangles included.
template <typename T>
T point_triangle_distance2(Point3<T> p, Point3<T> a, Point3<T> b, Point3<T> c) {
  const Point3<T> ab = b - a, ac = c - a, ap = p - a;
  const T d1 = dot(ab, ap), d2 = dot(ac, ap);
  auto dist2 = [&](Point3<T> q) { return dot(p - q, p - q); };
  if (d1 <= 0 && d2 <= 0) return dist2(a);
  const Point3<T> bp = p - b;
  const T d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return dist2(b);
  const T vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) return dist2(a + (d1 / (d1 - d3)) * ab);
  const Point3<T> cp = p - c;
  const T d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return dist2(c);
  const T vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) return dist2(a + (d2 / (d2 - d6)) * ac);
  const T va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0)
    return dist2(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
  const T sum = va + vb + vc;
  if (!(sum > 0)) {  // zero area: the nearest of the three edges
    auto segment = [&](Point3<T> s, Point3<T> e) {
      const Point3<T> d = e - s;
      const T len2 = dot(d, d);
      return dist2(len2 > 0 ? s + clamp01(dot(p - s, d) / len2) * d : s);
    };
    return std::min({segment(a, b), segment(b, c), segment(c, a)});
  }
  return dist2(a + (vb / sum) * ab + (vc / sum) * ac);
}

/// Squared distance between the closed segments (p0, p1) and (q0, q1)
/// (Ericson 5.1.9), zero-length segments included.
template <typename T>
T segment_segment_distance2(Point3<T> p0, Point3<T> p1, Point3<T> q0, Point3<T> q1) {
  const Point3<T> d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const T a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  T s = 0, t = 0;
  if (a <= 0 && e <= 0) {
    s = t = 0;
  } else if (a <= 0) {
    t = clamp01(f / e);
  } else {
    const T c = dot(d1, r);
    if (e <= 0) {
      s = clamp01(-c / a);
    } else {
      const T b = dot(d1, d2), denom = a * e - b * b;
      s = denom > 0 ? clamp01((b * f - c * e) / denom) : T(0);
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = clamp01(-c / a);
      } else if (t > 1) {
        t = 1;
        s = clamp01((b - c) / a);
      }
    }
  }
  const Point3<T> gap = (p0 + s * d1) - (q0 + t * d2);
  return dot(gap, gap);
}

/// f(t) = a t^3 + b t^2 + c t + d.
template <typename T>
struct Cubic {
  T a = 0, b = 0, c = 0, d = 0;
  T operator()(T t) const { return ((a * t + b) * t + c) * t + d; }
};

/// The coplanarity cubic of the four points x1..x4 (each at t0 and t1).
template <typename T>
Cubic<T> coplanarity_cubic(const std::array<Point3<T>, 8>& x) {
  const Point3<T> a0 = x[1] - x[0], b0 = x[2] - x[0], c0 = x[3] - x[0];
  const Point3<T> a1 = (x[5] - x[4]) - a0, b1 = (x[6] - x[4]) - b0, c1 = (x[7] - x[4]) - c0;
  Cubic<T> f;
  f.d = dot(cross(a0, b0), c0);
  f.c = dot(cross(a1, b0), c0) + dot(cross(a0, b1), c0) + dot(cross(a0, b0), c1);
  f.b = dot(cross(a1, b1), c0) + dot(cross(a1, b0), c1) + dot(cross(a0, b1), c1);
  f.a = dot(cross(a1, b1), c1);
  return f;
}

/// The roots of f in [0, 1], increasing; returns their count (at most 3).
/// f is split at the roots of f' into monotone pieces; a piece whose ends
/// have opposite signs is bisected to adjacent values of T.
template <typename T>
int unit_roots(const Cubic<T>& f, T roots[3]) {
  T cuts[4] = {0};
  int n_cuts = 1;
  const T qa = 3 * f.a, qb = 2 * f.b, qc = f.c;  // f'(t) = qa t^2 + qb t + qc
  T critical[2];
  int n_critical = 0;
  if (qa != 0) {
    const T disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const T s = std::sqrt(disc);
      critical[n_critical++] = (-qb - s) / (2 * qa);
      critical[n_critical++] = (-qb + s) / (2 * qa);
    }
  } else if (qb != 0) {
    critical[n_critical++] = -qc / qb;
  }
  std::sort(critical, critical + n_critical);
  for (int i = 0; i < n_critical; ++i)
    if (critical[i] > 0 && critical[i] < 1) cuts[n_cuts++] = critical[i];
  cuts[n_cuts++] = 1;
  int n = 0;
  for (int i = 0; i + 1 < n_cuts; ++i) {
    T lo = cuts[i], hi = cuts[i + 1];
    T f_lo = f(lo);
    const T f_hi = f(hi);
    if (f_lo == 0) {
      if (n == 0 || roots[n - 1] != lo) roots[n++] = lo;
      continue;
    }
    if (f_hi == 0 || (f_lo < 0) == (f_hi < 0)) continue;
    for (int iteration = 0; iteration < 200; ++iteration) {
      const T mid = lo + (hi - lo) / 2;
      if (!(mid > lo && mid < hi)) break;
      const T f_mid = f(mid);
      if (f_mid == 0) {
        lo = hi = mid;
        break;
      }
      if ((f_mid < 0) == (f_lo < 0)) {
        lo = mid;
        f_lo = f_mid;
      } else {
        hi = mid;
      }
    }
    if (n < 3) roots[n++] = lo + (hi - lo) / 2;
  }
  if (f(T(1)) == 0 && n < 3 && (n == 0 || roots[n - 1] != 1)) roots[n++] = 1;
  return n;
}

template <typename T>
std::array<Point3<T>, 4> at_time(const std::array<Point3<T>, 8>& x, T t) {
  std::array<Point3<T>, 4> p;
  for (int i = 0; i < 4; ++i) p[i] = (1 - t) * x[i] + t * x[i + 4];
  return p;
}

template <typename T>
bool cubic_ccd(const std::array<Vec3, 8>& points, bool edge_edge) {
  std::array<Point3<T>, 8> x;
  T lo[3] = {std::numeric_limits<T>::max(), std::numeric_limits<T>::max(), std::numeric_limits<T>::max()};
  T hi[3] = {-lo[0], -lo[1], -lo[2]};
  // Rounded to T; beyond T's range a value becomes an infinity (a plain
  // conversion would be undefined behaviour), and the cubic then has no root.
  auto rounded = [](double v) {
    const double top = double(std::numeric_limits<T>::max());
    return v > top ? std::numeric_limits<T>::infinity() : v < -top ? -std::numeric_limits<T>::infinity() : T(v);
  };
  for (int i = 0; i < 8; ++i) {
    x[i] = {rounded(points[i].x), rounded(points[i].y), rounded(points[i].z)};
    const T c[3] = {x[i].x, x[i].y, x[i].z};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
  }
  const T extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const T delta = std::sqrt(std::numeric_limits<T>::epsilon()) * extent;
  auto touches = [&](T t) {
    const auto p = at_time(x, t);
    const T d2 = edge_edge ? segment_segment_distance2(p[0], p[1], p[2], p[3])
                           : point_triangle_distance2(p[0], p[1], p[2], p[3]);
    return d2 <= delta * delta;
  };
  const Cubic<T> f = coplanarity_cubic(x);
  if (f.a == 0 && f.b == 0 && f.c == 0 && f.d == 0) return touches(T(0)) || touches(T(0.5)) || touches(T(1));
  T roots[3];
  const int n = unit_roots(f, roots);
  for (int i = 0; i < n; ++i)
    if (touches(roots[i])) return true;
  return false;
}

}  // namespace cubic_detail

/// Provot's cubic CCD in precision T (float or double) for one vertex-face
/// (edge_edge = false; points v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1,
/// f2_t1) or edge-edge query (ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1,
/// eb0_t1, eb1_t1). Positions in scene units, rounded to T first. True when
/// some root of the coplanarity cubic in [0, 1] passes the tolerance test
/// (see the top of this file). Never throws; not conservative: it misses
/// contacts and reports near misses, which is what snag-bench measures.
template <typename T>
bool provot_cubic_ccd(const std::array<Vec3, 8>& points, bool edge_edge) {
  return cubic_detail::cubic_ccd<T>(points, edge_edge);
}

}  // namespace snag::bench
