// Families of degenerate CCD queries, generated deterministically (fixed
// seeds, integer draws only, so every platform builds the same queries):
// the configurations of unwelded meshes (coincident vertices moving
// together), contacts at t = 0, features in one plane for the whole step,
// zero-length edges, collapsed triangles, zero and tiny motion, and huge and
// small coordinates. Coordinates are small integers or dyadic fractions of
// them, so that the coincidences, collinearities and coplanarities built in
// are exact in floating point; the scale family multiplies by non-dyadic
// factors on purpose.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"

namespace snag::test {

/// One query: points in the row order of the CCD query files (vertex-face:
/// p, a, b, c at t0 then at t1; edge-edge: ea0, ea1, eb0, eb1 at t0 then t1).
struct DegenerateQuery {
  std::array<Vec3, 8> points;
  bool edge_edge = false;
  double thickness = 0;
};

struct DegenerateFamily {
  std::string name;
  std::vector<DegenerateQuery> queries;
};

namespace degenerate_detail {

using Rng = std::mt19937_64;

/// An integer in [lo, hi] (modulo draw: the same on every standard library).
inline int integer(Rng& rng, int lo, int hi) {
  return lo + static_cast<int>(rng() % static_cast<std::uint64_t>(hi - lo + 1));
}
inline Vec3 integer_point(Rng& rng, int r) {
  return {double(integer(rng, -r, r)), double(integer(rng, -r, r)), double(integer(rng, -r, r))};
}
inline bool coin(Rng& rng) { return rng() % 2 == 0; }
/// a + k/4 (b - a): exact for the small integer points used here.
inline Vec3 on_segment(const Vec3& a, const Vec3& b, int quarters) { return a + (quarters / 4.0) * (b - a); }

inline DegenerateQuery query(bool edge_edge, std::array<Vec3, 4> t0, std::array<Vec3, 4> t1, double thickness = 0) {
  DegenerateQuery q;
  for (int i = 0; i < 4; ++i) {
    q.points[i] = t0[i];
    q.points[4 + i] = t1[i];
  }
  q.edge_edge = edge_edge;
  q.thickness = thickness;
  return q;
}

/// Four random integer points moved by random integer displacements (zero
/// for a point with probability 1/4).
inline void random_motion(Rng& rng, int r, int m, std::array<Vec3, 4>& t0, std::array<Vec3, 4>& t1) {
  for (int i = 0; i < 4; ++i) {
    t0[i] = integer_point(rng, r);
    t1[i] = rng() % 4 == 0 ? t0[i] : t0[i] + integer_point(rng, m);
  }
}

/// Adds, for every fourth query, a copy at a positive thickness.
inline void add_thick_copies(std::vector<DegenerateQuery>& queries, double thickness) {
  const std::size_t count = queries.size();
  for (std::size_t i = 0; i < count; i += 4) {
    DegenerateQuery q = queries[i];
    q.thickness = thickness;
    queries.push_back(q);
  }
}

}  // namespace degenerate_detail

/// A vertex coincident with a face corner, or edges sharing an end (or the
/// whole edge), at t = 0; half of them move together for the whole step.
inline DegenerateFamily coincident_vertices_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(101);
  DegenerateFamily family{"coincident vertex and face corner / edge ends", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 8, 4, t0, t1);
    const bool edge_edge = i % 2 == 1;
    const bool together = coin(rng);
    if (!edge_edge) {
      const int corner = integer(rng, 1, 3);
      t0[0] = t0[corner];
      if (together) t1[0] = t1[corner];
    } else if (rng() % 5 == 0) {  // a duplicated edge, maybe reversed
      const bool reversed = coin(rng);
      t0[2] = t0[reversed ? 1 : 0];
      t0[3] = t0[reversed ? 0 : 1];
      if (together) {
        t1[2] = t1[reversed ? 1 : 0];
        t1[3] = t1[reversed ? 0 : 1];
      }
    } else {
      const int end = integer(rng, 0, 1), other = integer(rng, 2, 3);
      t0[other] = t0[end];
      if (together) t1[other] = t1[end];
    }
    family.queries.push_back(query(edge_edge, t0, t1));
  }
  add_thick_copies(family.queries, 0.0625);
  return family;
}

/// A vertex on a face edge, or an edge end on the other edge's interior, at
/// t = 0; half of them stay on it for the whole step.
inline DegenerateFamily vertex_on_edge_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(102);
  DegenerateFamily family{"vertex on edge", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 8, 4, t0, t1);
    const bool edge_edge = i % 2 == 1;
    const int quarters = integer(rng, 1, 3);
    const bool stays = coin(rng);
    if (!edge_edge) {
      const int from = integer(rng, 1, 3), to = from == 3 ? 1 : from + 1;
      t0[0] = on_segment(t0[from], t0[to], quarters);
      if (stays) t1[0] = on_segment(t1[from], t1[to], quarters);
    } else {
      const int end = integer(rng, 2, 3);
      t0[end] = on_segment(t0[0], t0[1], quarters);
      if (stays) t1[end] = on_segment(t1[0], t1[1], quarters);
    }
    family.queries.push_back(query(edge_edge, t0, t1));
  }
  add_thick_copies(family.queries, 0.0625);
  return family;
}

/// All four points in one coordinate plane for the whole step (a vertex
/// sliding in the face's plane, coplanar edges), entering, leaving, passing
/// beside; the plane's axis and offset vary.
inline DegenerateFamily coplanar_motion_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(103);
  DegenerateFamily family{"in one plane for the whole step", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 6, 6, t0, t1);
    const int axis = integer(rng, 0, 2);
    const double offset = integer(rng, -3, 3);
    for (int k = 0; k < 4; ++k) {
      t0[k][axis] = offset;
      t1[k][axis] = offset;
    }
    family.queries.push_back(query(i % 2 == 1, t0, t1));
  }
  add_thick_copies(family.queries, 0.125);
  return family;
}

/// Two overlapping faces in one plane moving together (the same integer
/// displacement for all six corners; for a third of the pairs, one face also
/// slides in the plane): every VF and EE query between them.
inline DegenerateFamily overlapping_faces_family(int pairs = 20) {
  using namespace degenerate_detail;
  Rng rng(104);
  DegenerateFamily family{"overlapping coplanar faces moving together", {}};
  for (int i = 0; i < pairs; ++i) {
    const int axis = integer(rng, 0, 2);
    const double offset = integer(rng, -4, 4);
    std::array<Vec3, 3> f0, g0, f1, g1;
    const Vec3 shift = integer_point(rng, 2), motion = integer_point(rng, 5);
    Vec3 slide = rng() % 3 == 0 ? integer_point(rng, 2) : Vec3{0, 0, 0};
    slide[axis] = 0;
    for (int k = 0; k < 3; ++k) {
      f0[k] = integer_point(rng, 6);
      f0[k][axis] = offset;
      g0[k] = f0[(k + i) % 3] + shift;
      g0[k][axis] = offset;
      f1[k] = f0[k] + motion;
      g1[k] = g0[k] + motion + slide;
    }
    for (int side = 0; side < 2; ++side) {
      const auto& a0 = side == 0 ? f0 : g0;
      const auto& a1 = side == 0 ? f1 : g1;
      const auto& b0 = side == 0 ? g0 : f0;
      const auto& b1 = side == 0 ? g1 : f1;
      for (int v = 0; v < 3; ++v) {
        family.queries.push_back(query(false, {a0[v], b0[0], b0[1], b0[2]}, {a1[v], b1[0], b1[1], b1[2]}));
      }
    }
    for (int ea = 0; ea < 3; ++ea) {
      for (int eb = 0; eb < 3; ++eb) {
        const int ea_end = (ea + 1) % 3, eb_end = (eb + 1) % 3;
        family.queries.push_back(query(true, {f0[ea], f0[ea_end], g0[eb], g0[eb_end]},
                                       {f1[ea], f1[ea_end], g1[eb], g1[eb_end]}));
      }
    }
  }
  add_thick_copies(family.queries, 0.0625);
  return family;
}

/// Edges of zero length for the whole step (a point against an edge, or two
/// points), and faces with two coincident corners, passing through or beside
/// the other feature.
inline DegenerateFamily zero_length_edges_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(105);
  DegenerateFamily family{"zero-length edges", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 6, 4, t0, t1);
    const bool edge_edge = i % 2 == 1;
    if (edge_edge) {
      t0[1] = t0[0];
      t1[1] = t1[0];
      if (rng() % 4 == 0) {
        t0[3] = t0[2];
        t1[3] = t1[2];
      }
      // Steer the point through a point of the other edge at t = 1/2.
      if (coin(rng)) {
        const Vec3 target = on_segment(0.5 * (t0[2] + t1[2]), 0.5 * (t0[3] + t1[3]), integer(rng, 0, 4));
        const Vec3 half = 0.5 * (t0[0] + t1[0]);
        t0[0] = t0[0] + (target - half);
        t1[0] = t1[0] + (target - half);
        t0[1] = t0[0];
        t1[1] = t1[0];
      }
    } else {
      const int a = integer(rng, 1, 3), b = a == 3 ? 1 : a + 1;
      t0[b] = t0[a];
      t1[b] = t1[a];
    }
    family.queries.push_back(query(edge_edge, t0, t1));
  }
  add_thick_copies(family.queries, 0.0625);
  return family;
}

/// Faces collapsed to a segment or a point for the whole step (corners
/// collinear), with a vertex through or beside them; edge pairs on one line.
inline DegenerateFamily collapsed_triangles_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(106);
  DegenerateFamily family{"collapsed (zero-area) triangles", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 6, 4, t0, t1);
    if (i % 2 == 0) {
      const int quarters = integer(rng, 0, 4);
      t0[3] = on_segment(t0[1], t0[2], quarters);
      t1[3] = on_segment(t1[1], t1[2], quarters);
      if (rng() % 4 == 0) {  // a point
        t0[2] = t0[3] = t0[1];
        t1[2] = t1[3] = t1[1];
      }
      if (coin(rng)) {  // through the segment at t = 1/2
        const Vec3 target = on_segment(0.5 * (t0[1] + t1[1]), 0.5 * (t0[2] + t1[2]), integer(rng, 0, 4));
        const Vec3 half = 0.5 * (t0[0] + t1[0]);
        t0[0] = t0[0] + (target - half);
        t1[0] = t1[0] + (target - half);
      }
      family.queries.push_back(query(false, t0, t1));
    } else {  // all four ends on one moving line
      for (int k = 2; k < 4; ++k) {
        const int quarters = integer(rng, -4, 8);
        t0[k] = on_segment(t0[0], t0[1], quarters);
        t1[k] = on_segment(t1[0], t1[1], quarters);
      }
      family.queries.push_back(query(true, t0, t1));
    }
  }
  add_thick_copies(family.queries, 0.0625);
  return family;
}

/// No motion at all: touching, crossing, resting apart, degenerate or not.
inline DegenerateFamily zero_motion_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(107);
  DegenerateFamily family{"zero motion", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 4, 1, t0, t1);
    const bool edge_edge = i % 2 == 1;
    switch (rng() % 3) {
      case 0:  // in contact: a dyadic point of the face, or coplanar edges
        if (edge_edge) {
          const int axis = integer(rng, 0, 2);
          for (int k = 0; k < 4; ++k) t0[k][axis] = 1;
        } else {
          t0[0] = 0.25 * (t0[1] + t0[2] + 2.0 * t0[3]);
        }
        break;
      case 1:  // just apart: moved off by 2^-20
        if (edge_edge) {
          t0[2] = t0[2] + Vec3{0, 0, 0x1p-20};
        } else {
          t0[0] = 0.25 * (t0[1] + t0[2] + 2.0 * t0[3]) + Vec3{0x1p-20, 0, 0};
        }
        break;
      default:
        break;
    }
    t1 = t0;
    family.queries.push_back(query(edge_edge, t0, t1));
  }
  add_thick_copies(family.queries, 0.0625);
  return family;
}

/// Motion of 1e-12 on unit-sized features: contacts at the start that
/// persist, crossings of a 1e-13 gap, and near misses.
inline DegenerateFamily tiny_motion_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(108);
  DegenerateFamily family{"tiny motion (1e-12)", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 4, 0, t0, t1);
    const bool edge_edge = i % 2 == 1;
    if (edge_edge) {
      const int axis = integer(rng, 0, 2);
      for (int k = 0; k < 4; ++k) t0[k][axis] = 0;
      t0[2][axis] = integer(rng, -1, 1) * 1e-13;
    } else {
      t0[0] = 0.25 * (t0[1] + t0[2] + 2.0 * t0[3]);
      t0[0].z += integer(rng, -1, 1) * 1e-13;
    }
    for (int k = 0; k < 4; ++k) {
      const Vec3 direction = integer_point(rng, 2);
      t1[k] = t0[k] + 1e-12 * direction;
    }
    family.queries.push_back(query(edge_edge, t0, t1));
  }
  add_thick_copies(family.queries, 1e-13);
  return family;
}

/// Crossings and near misses at scales from 1e-6 to 1e6, some far from the
/// origin (offset 1e6), some with contact at t = 0.
inline DegenerateFamily scales_family(int count = 300) {
  using namespace degenerate_detail;
  Rng rng(109);
  DegenerateFamily family{"huge and small coordinates (1e-6 to 1e6)", {}};
  for (int i = 0; i < count; ++i) {
    std::array<Vec3, 4> t0, t1;
    random_motion(rng, 8, 8, t0, t1);
    const bool edge_edge = i % 2 == 1;
    if (rng() % 3 == 0) {  // contact at t = 0
      if (edge_edge) {
        t0[2] = on_segment(t0[0], t0[1], integer(rng, 0, 4));
      } else {
        t0[0] = on_segment(t0[1], t0[2], integer(rng, 0, 4));
      }
    }
    const double scale = std::pow(10.0, integer(rng, -6, 6));
    const Vec3 offset = rng() % 4 == 0 ? 1e6 * integer_point(rng, 1) : Vec3{0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      t0[k] = scale * t0[k] + offset;
      t1[k] = scale * t1[k] + offset;
    }
    family.queries.push_back(query(edge_edge, t0, t1, i % 5 == 0 ? scale / 16 : 0));
  }
  return family;
}

/// Every family above.
inline std::vector<DegenerateFamily> degenerate_families() {
  return {coincident_vertices_family(), vertex_on_edge_family(),    coplanar_motion_family(),
          overlapping_faces_family(),   zero_length_edges_family(), collapsed_triangles_family(),
          zero_motion_family(),         tiny_motion_family(),       scales_family()};
}

}  // namespace snag::test
