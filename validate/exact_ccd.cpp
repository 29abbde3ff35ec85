// Exact vertex–face and edge–edge CCD by root isolation and sign conditions.
//
// References:
//   B. Wang, Z. Ferguson, T. Schneider, X. Jiang, M. Attene, D. Panozzo,
//   "A Large Scale Benchmark and an Inclusion-Based Algorithm for Continuous
//   Collision Detection", ACM TOG 40(5), 2021 (the query sets and their
//   symbolic ground truth; the problem statement used here).
//   E. Berberich, M. Hemmer, M. Kerber, "Algebraic Kernel", CGAL User and
//   Reference Manual (Algebraic_kernel_d_1: real roots isolated with the
//   Descartes method of G. E. Collins and A. G. Akritas, "Polynomial real
//   root isolation using Descartes' rule of signs", SYMSAC 1976; exact signs
//   of polynomials at algebraic numbers).
//
// Method. Every position is linear in t with rational coefficients, so every
// quantity below is a polynomial in t with rational coefficients. The contact
// condition at one time t ("distance <= d") is written as a boolean formula
// C(t) over the signs of a fixed finite family F of such polynomials (the
// "atoms"), valid for every configuration, degenerate ones included:
//
//   point–point   |p - a|^2 - d^2 <= 0
//   point–segment [a, b], e = b - a, s = (p - a).e:
//       pp(p, a) or pp(p, b) or
//       (|e|^2 > 0 and s >= 0 and |e|^2 - s >= 0 and |e x (p - a)|^2 - d^2 |e|^2 <= 0)
//     (a zero-length segment is the point a, which the first disjunct covers;
//      otherwise the closest point is a, b or the foot at s / |e|^2 in (0, 1),
//      and |e x (p - a)|^2 / |e|^2 is the squared distance to the line.)
//   point–triangle (a, b, c), n = (b - a) x (c - a):
//       (|n|^2 > 0 and ((b-a) x (p-a)).n >= 0 and ((c-b) x (p-b)).n >= 0
//        and ((a-c) x (p-c)).n >= 0 and ((p-a).n)^2 - d^2 |n|^2 <= 0)
//       or point–segment with each of the three edges
//     (the first disjunct: the projection of p falls in the triangle, the three
//      dot products being |n|^2 times its barycentric coordinates, and the
//      distance is |(p-a).n| / |n|; otherwise the closest point is on the
//      boundary. A zero-area triangle, n = 0, is the convex hull of three
//      collinear points, which is the union of its three edges.)
//   segment–segment (a0, a1), (b0, b1), da = a1 - a0, db = b1 - b0,
//   w = b0 - a0, n = da x db:
//       (|n|^2 > 0 and 0 <= (w x db).n <= |n|^2 and 0 <= (w x da).n <= |n|^2
//        and (w.n)^2 - d^2 |n|^2 <= 0)
//       or point–segment for a0 and a1 against b, and for b0 and b1 against a
//     (the squared distance over the parameter square [0,1]^2 is a convex
//      quadratic; it is minimal at the interior point with parameters
//      (w x db).n / |n|^2 and (w x da).n / |n|^2 when the lines are not
//      parallel and that point is in the square, where the distance is
//      |w.n| / |n|; otherwise a minimum lies on the square's boundary, that
//      is an endpoint against the other segment. Parallel, collinear and
//      zero-length edges all have n = 0 and fall to the boundary terms.)
//
// With d = 0 these are exactly "the closed primitives share a point".
//
// Decisions by structure, before any root isolation. C at t = 0 is read from
// the signs of the atoms' constant coefficients (exact rationals): when it
// holds, t* = 0 exactly. When it does not and every atom is a constant
// polynomial (no motion, or all points translating together, so every
// difference of two points is constant), C is the same at every t: no
// contact.
//
// Why the earliest contact time is a candidate. Let S = { t in [0,1] : C(t) }.
// S is closed (the distance is continuous in t). Let R be {0, 1} and the real
// roots in [0, 1] of every atom that is not the zero polynomial. Between two
// consecutive elements of R every atom keeps its sign, so C is constant on
// each such open interval. If t* = min S were not in R, it would lie in such
// an interval on which C is true, and S would hold times earlier than t*.
// Hence t* is in R: testing C at the elements of R in increasing order and
// stopping at the first true one yields t* exactly. R is the fallback; the
// candidates used are smaller sets that still hold t* (with t* = 0 already
// excluded above):
//  - d = 0 and the coplanarity cubic det(b - a, c - a, p - a) (VF) or
//    det(da, db, w) (EE) not the zero polynomial: contact implies that the
//    four points are coplanar, so S lies within the cubic's roots in [0, 1]
//    (at most three candidates).
//  - otherwise, the roots in [0, 1] of the "distance atoms": the point–point
//    atoms, the off_line atoms, and (d > 0 only) the off_plane atom. Let
//    D(t) be the distance of the closed primitives, continuous in t. For
//    t* > 0, D > d on [0, t*) and D(t*) <= d, so D(t*) = d. At t* the
//    closest pair is given by one piece of C: the projection inside the
//    triangle or the lines' interior point (off_plane = 0 there), an end
//    point (point–point atom = 0) or a foot inside a segment (off_line = 0).
//    For d = 0 with the cubic the zero polynomial (coplanar for the whole
//    step) off_plane is identically 0 and is left out: there the interior
//    piece cannot be the one that starts the contact, because its conditions
//    (|n|^2 > 0 and strict barycentric or segment-parameter inequalities) are
//    open and would then hold, with off_plane = 0, just before t*; so at t*
//    an end point lies on the other feature (for parallel or collinear
//    segments too: their common part is bounded by end points), where a
//    point–point or an off_line atom vanishes. When a distance atom used is
//    the zero polynomial, its roots are not isolated points and R is used.
//
// Why the test at a candidate is exact. Each candidate is an algebraic real
// given by a square-free integer polynomial and an isolating interval with
// rational ends (CGAL::Algebraic_kernel_d_1 over Gmpz, after clearing
// denominators, which does not change signs). The sign of an atom at it is
// decided by Sign_at_1: zero exactly when the gcd with the defining
// polynomial vanishes there, otherwise by refining until the atom has no root
// in the interval and evaluating at a rational end. No floating point enters
// any decision; doubles appear only when the final interval is rounded
// outward for the caller.
#include "validate/exact_ccd.hpp"

#include <CGAL/Algebraic_kernel_d_1.h>
#include <CGAL/FPU.h>
#include <CGAL/Gmpq.h>
#include <CGAL/Gmpz.h>
#include <CGAL/Interval_nt.h>

#include <gmp.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "libcd/core/error.hpp"

namespace snag::validate {
namespace {

using Rational = CGAL::Gmpq;
using Integer = CGAL::Gmpz;
using AlgebraicKernel = CGAL::Algebraic_kernel_d_1<Integer>;
using AlgebraicReal = AlgebraicKernel::Algebraic_real_1;
using IntegerPolynomial = AlgebraicKernel::Polynomial_1;
using Bound = AlgebraicKernel::Bound;

// ---------------------------------------------------------------------------
// Univariate polynomials in t, lowest degree first, over a number type NT:
// Rational (exact) or Interval (each coefficient an interval that holds the
// exact one; see "The interval filter"). Trailing coefficients that are
// certainly zero are dropped, so the exact zero polynomial is empty.

/// Intervals with outward rounding; valid only under Protect_FPU_rounding.
using Interval = CGAL::Interval_nt_advanced;

template <class NT>
using PolyOf = std::vector<NT>;
using Poly = PolyOf<Rational>;

bool certainly_zero(const Rational& x) { return CGAL::is_zero(x); }
bool certainly_zero(const Interval& x) { return x.inf() == 0 && x.sup() == 0; }

template <class NT>
void trim(PolyOf<NT>& p) {
  while (!p.empty() && certainly_zero(p.back())) p.pop_back();
}

template <class NT>
PolyOf<NT> operator+(const PolyOf<NT>& a, const PolyOf<NT>& b) {
  PolyOf<NT> r(std::max(a.size(), b.size()), NT(0));
  for (std::size_t i = 0; i < a.size(); ++i) r[i] += a[i];
  for (std::size_t i = 0; i < b.size(); ++i) r[i] += b[i];
  trim(r);
  return r;
}

template <class NT>
PolyOf<NT> operator-(const PolyOf<NT>& a, const PolyOf<NT>& b) {
  PolyOf<NT> r(std::max(a.size(), b.size()), NT(0));
  for (std::size_t i = 0; i < a.size(); ++i) r[i] += a[i];
  for (std::size_t i = 0; i < b.size(); ++i) r[i] -= b[i];
  trim(r);
  return r;
}

template <class NT>
PolyOf<NT> operator*(const PolyOf<NT>& a, const PolyOf<NT>& b) {
  if (a.empty() || b.empty()) return {};
  PolyOf<NT> r(a.size() + b.size() - 1, NT(0));
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) r[i + j] += a[i] * b[j];
  trim(r);
  return r;
}

template <class NT>
PolyOf<NT> scaled(const PolyOf<NT>& a, const NT& s) {
  PolyOf<NT> r = a;
  for (auto& c : r) c *= s;
  trim(r);
  return r;
}

template <class NT>
struct PolyVec3Of {
  PolyOf<NT> x, y, z;
};
using PolyVec3 = PolyVec3Of<Rational>;

template <class NT>
PolyVec3Of<NT> operator-(const PolyVec3Of<NT>& a, const PolyVec3Of<NT>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class NT>
PolyOf<NT> dot(const PolyVec3Of<NT>& a, const PolyVec3Of<NT>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class NT>
PolyVec3Of<NT> cross(const PolyVec3Of<NT>& a, const PolyVec3Of<NT>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class NT>
PolyOf<NT> squared_norm(const PolyVec3Of<NT>& a) {
  return dot(a, a);
}

/// The linear motion x_t0 + t (x_t1 - x_t0) of one coordinate.
template <class NT>
PolyOf<NT> linear_motion(const NT& x_t0, const NT& x_t1) {
  PolyOf<NT> p{x_t0, x_t1 - x_t0};
  trim(p);
  return p;
}

template <class NT>
using PointOf = std::array<NT, 3>;
using RationalPoint = PointOf<Rational>;

template <class NT>
PolyVec3Of<NT> linear_motion(const PointOf<NT>& p_t0, const PointOf<NT>& p_t1) {
  return {linear_motion(p_t0[0], p_t1[0]), linear_motion(p_t0[1], p_t1[1]), linear_motion(p_t0[2], p_t1[2])};
}

/// p times the positive lcm of its denominators: same signs, integer coefficients.
IntegerPolynomial to_integer_polynomial(const Poly& p) {
  Integer common(1);
  for (const auto& c : p) {
    Integer den = c.denominator();
    common = common / CGAL::gcd(common, den) * den;
  }
  std::vector<Integer> coefficients;
  coefficients.reserve(p.size());
  for (const auto& c : p) coefficients.push_back(c.numerator() * (common / c.denominator()));
  if (coefficients.empty()) coefficients.push_back(Integer(0));
  return IntegerPolynomial(coefficients.begin(), coefficients.end());
}

// ---------------------------------------------------------------------------
// The atoms, and their signs at one candidate time.

/// The atoms of one query, each a polynomial over NT. The same builders
/// (add_point_triangle, add_segment_segment) give both systems of a query
/// the same atom numbers.
template <class NT>
class SignSystemOf {
 public:
  int add(const PolyOf<NT>& p) {
    polys_.push_back(p);
    return static_cast<int>(polys_.size()) - 1;
  }

  std::size_t size() const { return polys_.size(); }
  const PolyOf<NT>& poly(std::size_t i) const { return polys_[i]; }

 private:
  std::vector<PolyOf<NT>> polys_;
};

/// The exact atoms, with their integer forms for the algebraic kernel.
class SignSystem : public SignSystemOf<Rational> {
 public:
  /// poly(i) with integer coefficients, converted on first use.
  const IntegerPolynomial& integer_poly(std::size_t i) const {
    if (integer_polys_.size() < size()) {
      integer_polys_.resize(size());
      converted_.resize(size(), false);
    }
    if (!converted_[i]) {
      integer_polys_[i] = to_integer_polynomial(poly(i));
      converted_[i] = true;
    }
    return integer_polys_[i];
  }

 private:
  mutable std::vector<IntegerPolynomial> integer_polys_;
  mutable std::vector<bool> converted_;
};

/// Signs of the atoms at one algebraic time, computed on demand.
class SignsAt {
 public:
  SignsAt(const SignSystem& system, const AlgebraicReal& t)
      : system_(system), t_(t), signs_(system.size(), kUnknown) {}

  int operator()(int atom) {
    signed char& s = signs_[static_cast<std::size_t>(atom)];
    if (s == kUnknown) {
      const Poly& p = system_.poly(static_cast<std::size_t>(atom));
      if (p.empty())
        s = 0;
      else if (p.size() == 1)
        s = static_cast<signed char>(CGAL::sign(p[0]));
      else
        s = static_cast<signed char>(
            AlgebraicKernel::Sign_at_1()(system_.integer_poly(static_cast<std::size_t>(atom)), t_));
    }
    return s;
  }

 private:
  static constexpr signed char kUnknown = 2;
  const SignSystem& system_;
  const AlgebraicReal& t_;
  std::vector<signed char> signs_;
};

/// Signs of the atoms at t = 0: the signs of their constant coefficients.
class SignsAtStart {
 public:
  explicit SignsAtStart(const SignSystem& system) : system_(system) {}
  int operator()(int atom) const {
    const Poly& p = system_.poly(static_cast<std::size_t>(atom));
    return p.empty() ? 0 : CGAL::sign(p[0]);
  }

 private:
  const SignSystem& system_;
};

struct PointPointAtoms {
  int distance;  // |p - a|^2 - d^2, <= 0
};

struct PointSegmentAtoms {
  PointPointAtoms end_a, end_b;
  int length;     // |e|^2, > 0
  int along;      // (p - a).e, >= 0
  int along_rest; // |e|^2 - (p - a).e, >= 0
  int off_line;   // |e x (p - a)|^2 - d^2 |e|^2, <= 0
};

struct PointTriangleAtoms {
  int normal;          // |n|^2, > 0
  int barycentric[3];  // >= 0 each
  int off_plane;       // ((p - a).n)^2 - d^2 |n|^2, <= 0
  PointSegmentAtoms edges[3];
};

struct SegmentSegmentAtoms {
  int normal;                  // |n|^2, > 0
  int along_a, along_a_rest;   // (w x db).n and |n|^2 - (w x db).n, >= 0
  int along_b, along_b_rest;   // (w x da).n and |n|^2 - (w x da).n, >= 0
  int off_plane;               // (w.n)^2 - d^2 |n|^2, <= 0
  PointSegmentAtoms ends[4];   // a0, a1 against b; b0, b1 against a
};

// The coplanarity cubics: zero exactly when the four points are coplanar.
// Each is the plane atom's w.n, or (p - a).n, so the plane atom is its
// square when d = 0.
template <class NT>
PolyOf<NT> vertex_face_coplanarity(const PolyVec3Of<NT>& p, const PolyVec3Of<NT>& a, const PolyVec3Of<NT>& b,
                                   const PolyVec3Of<NT>& c) {
  return dot(p - a, cross(b - a, c - a));
}

template <class NT>
PolyOf<NT> edge_edge_coplanarity(const PolyVec3Of<NT>& a0, const PolyVec3Of<NT>& a1, const PolyVec3Of<NT>& b0,
                                 const PolyVec3Of<NT>& b1) {
  return dot(b0 - a0, cross(a1 - a0, b1 - b0));
}

template <class NT>
PointPointAtoms add_point_point(SignSystemOf<NT>& system, const PolyVec3Of<NT>& p, const PolyVec3Of<NT>& a,
                                const NT& d2) {
  return {system.add(squared_norm(p - a) - PolyOf<NT>{d2})};
}

template <class NT>
PointSegmentAtoms add_point_segment(SignSystemOf<NT>& system, const PolyVec3Of<NT>& p, const PolyVec3Of<NT>& a,
                                    const PolyVec3Of<NT>& b, const NT& d2) {
  const PolyVec3Of<NT> e = b - a;
  const PolyVec3Of<NT> pa = p - a;
  const PolyOf<NT> length = squared_norm(e);
  const PolyOf<NT> along = dot(pa, e);
  PointSegmentAtoms atoms;
  atoms.end_a = add_point_point(system, p, a, d2);
  atoms.end_b = add_point_point(system, p, b, d2);
  atoms.length = system.add(length);
  atoms.along = system.add(along);
  atoms.along_rest = system.add(length - along);
  atoms.off_line = system.add(squared_norm(cross(e, pa)) - scaled(length, d2));
  return atoms;
}

template <class NT>
PointTriangleAtoms add_point_triangle(SignSystemOf<NT>& system, const PolyVec3Of<NT>& p, const PolyVec3Of<NT>& a,
                                      const PolyVec3Of<NT>& b, const PolyVec3Of<NT>& c, const NT& d2) {
  const PolyVec3Of<NT> n = cross(b - a, c - a);
  const PolyOf<NT> normal = squared_norm(n);
  const PolyOf<NT> plane = dot(p - a, n);
  PointTriangleAtoms atoms;
  atoms.normal = system.add(normal);
  atoms.barycentric[0] = system.add(dot(cross(b - a, p - a), n));
  atoms.barycentric[1] = system.add(dot(cross(c - b, p - b), n));
  atoms.barycentric[2] = system.add(dot(cross(a - c, p - c), n));
  atoms.off_plane = system.add(plane * plane - scaled(normal, d2));
  atoms.edges[0] = add_point_segment(system, p, a, b, d2);
  atoms.edges[1] = add_point_segment(system, p, b, c, d2);
  atoms.edges[2] = add_point_segment(system, p, c, a, d2);
  return atoms;
}

template <class NT>
SegmentSegmentAtoms add_segment_segment(SignSystemOf<NT>& system, const PolyVec3Of<NT>& a0,
                                        const PolyVec3Of<NT>& a1, const PolyVec3Of<NT>& b0,
                                        const PolyVec3Of<NT>& b1, const NT& d2) {
  const PolyVec3Of<NT> da = a1 - a0, db = b1 - b0, w = b0 - a0;
  const PolyVec3Of<NT> n = cross(da, db);
  const PolyOf<NT> normal = squared_norm(n);
  const PolyOf<NT> along_a = dot(cross(w, db), n);
  const PolyOf<NT> along_b = dot(cross(w, da), n);
  const PolyOf<NT> plane = dot(w, n);
  SegmentSegmentAtoms atoms;
  atoms.normal = system.add(normal);
  atoms.along_a = system.add(along_a);
  atoms.along_a_rest = system.add(normal - along_a);
  atoms.along_b = system.add(along_b);
  atoms.along_b_rest = system.add(normal - along_b);
  atoms.off_plane = system.add(plane * plane - scaled(normal, d2));
  atoms.ends[0] = add_point_segment(system, a0, b0, b1, d2);
  atoms.ends[1] = add_point_segment(system, a1, b0, b1, d2);
  atoms.ends[2] = add_point_segment(system, b0, a0, a1, d2);
  atoms.ends[3] = add_point_segment(system, b1, a0, a1, d2);
  return atoms;
}

template <class Sign>
bool holds(const PointPointAtoms& atoms, Sign& sign) { return sign(atoms.distance) <= 0; }

template <class Sign>
bool holds(const PointSegmentAtoms& atoms, Sign& sign) {
  if (holds(atoms.end_a, sign) || holds(atoms.end_b, sign)) return true;
  return sign(atoms.length) > 0 && sign(atoms.along) >= 0 && sign(atoms.along_rest) >= 0 &&
         sign(atoms.off_line) <= 0;
}

template <class Sign>
bool holds(const PointTriangleAtoms& atoms, Sign& sign) {
  if (sign(atoms.normal) > 0 && sign(atoms.off_plane) <= 0 && sign(atoms.barycentric[0]) >= 0 &&
      sign(atoms.barycentric[1]) >= 0 && sign(atoms.barycentric[2]) >= 0)
    return true;
  for (const auto& edge : atoms.edges)
    if (holds(edge, sign)) return true;
  return false;
}

template <class Sign>
bool holds(const SegmentSegmentAtoms& atoms, Sign& sign) {
  if (sign(atoms.normal) > 0 && sign(atoms.off_plane) <= 0 && sign(atoms.along_a) >= 0 &&
      sign(atoms.along_a_rest) >= 0 && sign(atoms.along_b) >= 0 && sign(atoms.along_b_rest) >= 0)
    return true;
  for (const auto& end : atoms.ends)
    if (holds(end, sign)) return true;
  return false;
}

// The distance atoms: those that vanish where the distance of the closest
// pair is exactly d (see the file comment); the plane atom only when
// `with_plane`.
void append_distance_atoms(const PointPointAtoms& atoms, std::vector<int>& out) { out.push_back(atoms.distance); }

void append_distance_atoms(const PointSegmentAtoms& atoms, std::vector<int>& out) {
  append_distance_atoms(atoms.end_a, out);
  append_distance_atoms(atoms.end_b, out);
  out.push_back(atoms.off_line);
}

void append_distance_atoms(const PointTriangleAtoms& atoms, bool with_plane, std::vector<int>& out) {
  if (with_plane) out.push_back(atoms.off_plane);
  for (const auto& edge : atoms.edges) append_distance_atoms(edge, out);
}

void append_distance_atoms(const SegmentSegmentAtoms& atoms, bool with_plane, std::vector<int>& out) {
  if (with_plane) out.push_back(atoms.off_plane);
  for (const auto& end : atoms.ends) append_distance_atoms(end, out);
}

// ---------------------------------------------------------------------------
// Candidates and the search for the earliest contact.

/// Appends the real roots of p in [0, 1] (p not the zero polynomial).
void append_roots_in_unit_interval(const Poly& p, std::vector<AlgebraicReal>& out) {
  if (p.size() <= 1) return;
  AlgebraicKernel::Solve_1()(to_integer_polynomial(p), false, Bound(0), Bound(1),
                             std::back_inserter(out));
}

void sort_unique(std::vector<AlgebraicReal>& values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
}

std::string to_text(const Rational& q) {
  std::ostringstream out;
  out << q.numerator() << "/" << q.denominator();
  return out.str();
}

/// The smallest prec with 2^-prec <= toi_width.
int toi_precision(double toi_width) { return static_cast<int>(std::ceil(-std::log2(toi_width))); }

ExactCcdResult describe_contact(const AlgebraicReal& toi, double toi_width) {
  std::pair<Bound, Bound> bounds = AlgebraicKernel::Approximate_absolute_1()(toi, toi_precision(toi_width));
  Bound lo = CGAL::max(bounds.first, Bound(0));
  Bound hi = CGAL::min(bounds.second, Bound(1));
  ExactCcdResult result;
  result.collides = true;
  result.toi_lo = CGAL::to_interval(lo).first;
  result.toi_hi = CGAL::to_interval(hi).second;
  result.toi_lo_exact = to_text(lo);
  result.toi_hi_exact = to_text(hi);
  return result;
}

/// A contact at exactly t = 0.
ExactCcdResult contact_at_start() {
  ExactCcdResult result;
  result.collides = true;
  result.toi_lo = result.toi_hi = 0;
  result.toi_lo_exact = result.toi_hi_exact = to_text(Rational(0));
  return result;
}

template <class Atoms>
ExactCcdResult earliest_contact(const SignSystem& system, const Atoms& atoms,
                                const Poly& coplanarity, bool zero_thickness, double toi_width) {
  // Decided by structure: contact at t = 0, or atoms that never change sign.
  SignsAtStart sign_at_start(system);
  if (holds(atoms, sign_at_start)) return contact_at_start();
  bool all_constant = true;
  for (std::size_t i = 0; i < system.size() && all_constant; ++i) all_constant = system.poly(i).size() <= 1;
  if (all_constant) return {};

  std::vector<AlgebraicReal> candidates;
  if (zero_thickness && !coplanarity.empty()) {
    append_roots_in_unit_interval(coplanarity, candidates);
  } else {
    std::vector<int> distance_atoms;
    append_distance_atoms(atoms, !zero_thickness, distance_atoms);
    std::vector<const Poly*> distinct;  // the same atom appears for two edges
    bool vanishing = false;              // a distance atom is the zero polynomial
    for (int atom : distance_atoms) {
      const Poly& p = system.poly(static_cast<std::size_t>(atom));
      vanishing = vanishing || p.empty();
      if (std::none_of(distinct.begin(), distinct.end(), [&p](const Poly* q) { return *q == p; }))
        distinct.push_back(&p);
    }
    if (vanishing) {
      candidates.push_back(AlgebraicKernel::Construct_algebraic_real_1()(1));
      for (std::size_t i = 0; i < system.size(); ++i)
        append_roots_in_unit_interval(system.poly(i), candidates);
    } else {
      for (const Poly* p : distinct) append_roots_in_unit_interval(*p, candidates);
    }
  }
  sort_unique(candidates);
  for (const auto& t : candidates) {
    SignsAt sign(system, t);
    if (holds(atoms, sign)) return describe_contact(t, toi_width);
  }
  return {};
}

// ---------------------------------------------------------------------------
// The interval filter.
//
// Queries given as doubles with zero thickness are first decided with
// interval arithmetic, which is exact when it decides. The atoms are built a
// second time, with the same builders, from the same doubles, in intervals
// (outward rounding) whose every coefficient holds the exact rational one.
// Evaluated (Horner) at an interval of times holding t, an atom's interval
// holds its exact value at t: when the interval excludes zero, or is exactly
// [0, 0], it gives the exact sign. The decisions are then the rational
// method's, in its order:
//  - contact at t = 0: the atoms' signs at t = [0, 0];
//  - the candidates: the roots in [0, 1] of the coplanarity cubic, computed
//    exactly (a few rational products) and isolated by the algebraic kernel,
//    as the rational method does; the atoms are evaluated over each root's
//    isolating interval refined to the answer's width (toi_width), and
//    once more refined to 2^-52 when that does not decide;
//  - at a root of the cubic the plane atom is exactly zero: with d = 0 it is
//    the square of the cubic itself (off_plane = (w.n)^2, and the cubic is
//    w.n, or (p - a).n for a vertex and a face), so its sign is taken as 0
//    without evaluation.
// When any sign the decision needs is not decided (an interval holds zero
// and is not [0, 0]), or the cubic is the zero polynomial (coplanar for the
// whole step), or the thickness is not zero, the filter gives up and the
// rational method decides the query from the start.

/// Signs of the interval atoms over an interval of times; undecided() once
/// a sign asked for was not decided (the answer given for it then is 0).
class IntervalSignsAt {
 public:
  /// known_zero: an atom exactly zero at every time of `t` (-1: none).
  IntervalSignsAt(const SignSystemOf<Interval>& system, Interval t, int known_zero)
      : system_(system), t_(t), known_zero_(known_zero) {}

  int operator()(int atom) {
    if (atom == known_zero_) return 0;
    const PolyOf<Interval>& p = system_.poly(static_cast<std::size_t>(atom));
    Interval value(0);
    for (auto c = p.rbegin(); c != p.rend(); ++c) value = value * t_ + *c;
    if (value.inf() > 0) return 1;
    if (value.sup() < 0) return -1;
    undecided_ = undecided_ || !certainly_zero(value);
    return 0;
  }
  bool undecided() const { return undecided_; }

 private:
  const SignSystemOf<Interval>& system_;
  Interval t_;
  int known_zero_;
  bool undecided_ = false;
};

/// Whether the atoms hold over the times `t`, or nullopt when a sign the
/// answer needs is not decided. Interval arithmetic runs only in here.
template <class Atoms>
std::optional<bool> holds_over(const SignSystemOf<Interval>& system, const Atoms& atoms, Interval t, int known_zero) {
  CGAL::Protect_FPU_rounding<true> upward;
  IntervalSignsAt sign(system, t, known_zero);
  const bool answer = holds(atoms, sign);
  if (sign.undecided()) return std::nullopt;
  return answer;
}

/// The times held by the isolating interval of t, refined to 2^-prec or less.
Interval times_around(const AlgebraicReal& t, int prec) {
  const std::pair<Bound, Bound> bounds = AlgebraicKernel::Approximate_absolute_1()(t, prec);
  return Interval(CGAL::to_interval(bounds.first).first, CGAL::to_interval(bounds.second).second);
}

ExactCcdResult by_filter(ExactCcdResult result) {
  result.filtered = true;
  return result;
}

/// earliest_contact for zero thickness, decided in intervals where they
/// suffice (see above); nullopt where the rational method must decide.
template <class Atoms>
std::optional<ExactCcdResult> filtered_earliest_contact(const SignSystemOf<Interval>& system, const Atoms& atoms,
                                                        int plane_atom, const Poly& coplanarity,
                                                        double toi_width) {
  const std::optional<bool> at_start = holds_over(system, atoms, Interval(0), -1);
  if (!at_start) return std::nullopt;
  if (*at_start) return by_filter(contact_at_start());
  if (coplanarity.empty()) return std::nullopt;
  // A constant cubic has no roots: no contact, as the rational method finds
  // (its atoms are then all constant, or the cubic's roots are searched).
  std::vector<AlgebraicReal> candidates;
  append_roots_in_unit_interval(coplanarity, candidates);
  sort_unique(candidates);
  for (const auto& t : candidates) {
    // First as narrow as the answer's interval must be, then narrower.
    std::optional<bool> contact = holds_over(system, atoms, times_around(t, toi_precision(toi_width)), plane_atom);
    if (!contact) contact = holds_over(system, atoms, times_around(t, 52), plane_atom);
    if (!contact) return std::nullopt;
    if (*contact) return by_filter(describe_contact(t, toi_width));
  }
  return by_filter(ExactCcdResult{});
}

void check_parameters(double thickness, double toi_width) {
  if (!std::isfinite(thickness) || thickness < 0)
    throw UsageError("exact CCD: thickness must be finite and >= 0");
  if (!std::isfinite(toi_width) || toi_width <= 0)
    throw UsageError("exact CCD: toi_width must be finite and > 0");
}

Rational to_rational(double x) {
  if (!std::isfinite(x)) throw UsageError("exact CCD: coordinate is not finite");
  return Rational(x);
}

Rational to_rational(const std::string& text) {
  mpq_t q;
  mpq_init(q);
  const bool parsed = !text.empty() && text.find_first_of(" \t\n") == std::string::npos &&
                      mpq_set_str(q, text.c_str(), 10) == 0 && mpz_sgn(mpq_denref(q)) != 0;
  if (!parsed) {
    mpq_clear(q);
    throw UsageError("exact CCD: '" + text + "' is not a rational num/den");
  }
  mpq_canonicalize(q);
  Rational r(q);
  mpq_clear(q);
  return r;
}

RationalPoint to_rational(const Vec3& p) { return {to_rational(p.x), to_rational(p.y), to_rational(p.z)}; }
RationalPoint to_rational(const RationalVec3& p) {
  return {to_rational(p.x), to_rational(p.y), to_rational(p.z)};
}

template <class Point>
std::array<PolyVec3, 4> motions(const std::array<Point, 8>& points) {
  std::array<PolyVec3, 4> m;
  for (std::size_t i = 0; i < 4; ++i) m[i] = linear_motion(to_rational(points[i]), to_rational(points[i + 4]));
  return m;
}

/// The two kinds of query: their atoms and coplanarity cubic, from the
/// motions of their four points (in the row order of the query files).
struct VertexFace {
  template <class NT>
  static PointTriangleAtoms atoms(SignSystemOf<NT>& system, const std::array<PolyVec3Of<NT>, 4>& m, const NT& d2) {
    return add_point_triangle(system, m[0], m[1], m[2], m[3], d2);
  }
  template <class NT>
  static PolyOf<NT> coplanarity(const std::array<PolyVec3Of<NT>, 4>& m) {
    return vertex_face_coplanarity(m[0], m[1], m[2], m[3]);
  }
};

struct EdgeEdge {
  template <class NT>
  static SegmentSegmentAtoms atoms(SignSystemOf<NT>& system, const std::array<PolyVec3Of<NT>, 4>& m, const NT& d2) {
    return add_segment_segment(system, m[0], m[1], m[2], m[3], d2);
  }
  template <class NT>
  static PolyOf<NT> coplanarity(const std::array<PolyVec3Of<NT>, 4>& m) {
    return edge_edge_coplanarity(m[0], m[1], m[2], m[3]);
  }
};

/// The rational method.
template <class Kind, class Point>
ExactCcdResult rational_ccd(const std::array<Point, 8>& points, double thickness, double toi_width) {
  check_parameters(thickness, toi_width);
  const std::array<PolyVec3, 4> m = motions(points);
  const Rational d = to_rational(thickness);
  SignSystem system;
  const auto atoms = Kind::atoms(system, m, d * d);
  return earliest_contact(system, atoms, Kind::coplanarity(m), thickness == 0, toi_width);
}

/// The points' motions in intervals, or nullopt when a coordinate is not
/// finite (the rational method then names the problem).
std::optional<std::array<PolyVec3Of<Interval>, 4>> interval_motions(const std::array<Vec3, 8>& points) {
  for (const Vec3& x : points)
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return std::nullopt;
  CGAL::Protect_FPU_rounding<true> upward;
  std::array<PolyVec3Of<Interval>, 4> m;
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec3& x0 = points[i];
    const Vec3& x1 = points[i + 4];
    m[i] = linear_motion(PointOf<Interval>{Interval(x0.x), Interval(x0.y), Interval(x0.z)},
                         PointOf<Interval>{Interval(x1.x), Interval(x1.y), Interval(x1.z)});
  }
  return m;
}

/// The interval filter, then the rational method if it must.
template <class Kind>
ExactCcdResult filtered_ccd(const std::array<Vec3, 8>& points, double thickness, double toi_width) {
  check_parameters(thickness, toi_width);
  if (thickness == 0) {
    if (const auto motion = interval_motions(points)) {
      SignSystemOf<Interval> system;
      const auto atoms = [&] {
        CGAL::Protect_FPU_rounding<true> upward;
        return Kind::atoms(system, *motion, Interval(0));
      }();
      const Poly coplanarity = Kind::coplanarity(motions(points));
      if (auto result = filtered_earliest_contact(system, atoms, atoms.off_plane, coplanarity, toi_width))
        return *result;
    }
  }
  return rational_ccd<Kind>(points, thickness, toi_width);
}

}  // namespace

ExactCcdResult exact_vertex_face_ccd(const std::array<Vec3, 8>& points, double thickness, double toi_width,
                                     ExactMethod method) {
  return method == ExactMethod::kFiltered ? filtered_ccd<VertexFace>(points, thickness, toi_width)
                                          : rational_ccd<VertexFace>(points, thickness, toi_width);
}

ExactCcdResult exact_edge_edge_ccd(const std::array<Vec3, 8>& points, double thickness, double toi_width,
                                   ExactMethod method) {
  return method == ExactMethod::kFiltered ? filtered_ccd<EdgeEdge>(points, thickness, toi_width)
                                          : rational_ccd<EdgeEdge>(points, thickness, toi_width);
}

ExactCcdResult exact_vertex_face_ccd(const std::array<RationalVec3, 8>& points, double thickness,
                                     double toi_width) {
  return rational_ccd<VertexFace>(points, thickness, toi_width);
}

ExactCcdResult exact_edge_edge_ccd(const std::array<RationalVec3, 8>& points, double thickness,
                                   double toi_width) {
  return rational_ccd<EdgeEdge>(points, thickness, toi_width);
}

}  // namespace snag::validate
