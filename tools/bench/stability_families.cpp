#include "tools/bench/stability_families.hpp"

#include <cmath>
#include <random>

#include "libcd/core/error.hpp"

namespace snag::bench {

namespace {

using Rng = std::mt19937_64;
using Generator = CcdQueryPoints (*)(double knob, Rng& rng);

double uniform(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
/// -1 or +1 with equal odds: a hit or a near miss.
double random_sign(Rng& rng) { return rng() & 1 ? 1.0 : -1.0; }
/// -1, 0 or +1: the exact contact (0) is one case in three.
double random_sign_or_zero(Rng& rng) { return double(int(rng() % 3) - 1); }

/// A random rotation (unit quaternion from three uniforms, Shoemake 1992) applied to every point.
void rotate(CcdQueryPoints& q, Rng& rng) {
  const double u1 = uniform(rng, 0, 1), u2 = uniform(rng, 0, 2 * M_PI), u3 = uniform(rng, 0, 2 * M_PI);
  const double w = std::sqrt(1 - u1) * std::sin(u2), x = std::sqrt(1 - u1) * std::cos(u2),
               y = std::sqrt(u1) * std::sin(u3), z = std::sqrt(u1) * std::cos(u3);
  for (Vec3& p : q.points) {
    const Vec3 r{(1 - 2 * (y * y + z * z)) * p.x + 2 * (x * y - w * z) * p.y + 2 * (x * z + w * y) * p.z,
                 2 * (x * y + w * z) * p.x + (1 - 2 * (x * x + z * z)) * p.y + 2 * (y * z - w * x) * p.z,
                 2 * (x * z - w * y) * p.x + 2 * (y * z + w * x) * p.y + (1 - 2 * (x * x + y * y)) * p.z};
    p = r;
  }
}

/// Tilts the plane z = 0 without rounding: x and y are moved to multiples of
/// 2^-20, then z += x / 2 + y / 4, exact in doubles for |x|, |y| < 2^30.
/// The map is affine, so what touches still touches (a contact exactly in
/// the plane stays exact) and what is apart by the knob stays about as far.
void tilt(CcdQueryPoints& q) {
  for (Vec3& p : q.points) {
    p.x = std::round(std::ldexp(p.x, 20)) / (1 << 20);
    p.y = std::round(std::ldexp(p.y, 20)) / (1 << 20);
    p.z += p.x / 2 + p.y / 4;
  }
}

/// A static triangle near the unit right triangle of the plane z = 0.
void static_triangle(CcdQueryPoints& q, Rng& rng) {
  q.points[1] = {uniform(rng, -0.1, 0), uniform(rng, -0.05, 0.05), 0};
  q.points[2] = {uniform(rng, 1, 1.1), uniform(rng, -0.05, 0.05), 0};
  q.points[3] = {uniform(rng, -0.1, 0.1), uniform(rng, 1, 1.1), 0};
  for (int i = 1; i < 4; ++i) q.points[i + 4] = q.points[i];
}

/// A static edge along the x axis, from about 0 to about 1.
void static_edge(CcdQueryPoints& q, Rng& rng) {
  q.points[0] = q.points[4] = {uniform(rng, -0.1, 0), 0, 0};
  q.points[1] = q.points[5] = {uniform(rng, 1, 1.1), 0, 0};
}

// Vertex and triangle in the plane z = 0 for the whole step; the vertex moves
// toward the triangle's edge along y = 0 and stops `knob` short of it or
// `knob` past it.
CcdQueryPoints vf_coplanar(double knob, Rng& rng) {
  CcdQueryPoints q;
  q.points[1] = {0, 0, 0};
  q.points[2] = {1, 0, 0};
  q.points[3] = {uniform(rng, 0, 1), 1, 0};
  for (int i = 1; i < 4; ++i) q.points[i + 4] = q.points[i];
  const double x = uniform(rng, 0.2, 0.8);
  q.points[0] = {x, -1, 0};
  q.points[4] = {x + uniform(rng, -0.1, 0.1), random_sign(rng) * knob, 0};
  return q;
}

// Both edges in the plane z = 0 for the whole step; edge b's upper end moves
// toward edge a and stops `knob` short of it or `knob` past it.
CcdQueryPoints ee_coplanar(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_edge(q, rng);
  const double x = uniform(rng, 0.2, 0.8), end = random_sign(rng) * knob;
  q.points[2] = {x, -1, 0};
  q.points[3] = {x + 0.2, -1.5, 0};
  q.points[6] = {x, end, 0};
  q.points[7] = {x + 0.2, end - 0.5, 0};
  return q;
}

// Edge b, turned by `knob` radians from edge a in a parallel plane, passes
// through edge a's line; offset sideways so that about half the samples
// cross edge a and half pass beside it (at knob -> 0 the edges are parallel,
// and collinear at the moment of contact when the offset rounds to 0).
CcdQueryPoints ee_parallel(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_edge(q, rng);
  const double half = 0.4, reach = half * std::sin(knob);
  const double offset = random_sign(rng) * reach * uniform(rng, 0.5, 1.5);
  const Vec3 along{std::cos(knob), std::sin(knob), 0};
  const Vec3 centre{0.5, offset, 0};
  for (int i = 0; i < 2; ++i) {
    const Vec3 lift{0, 0, i == 0 ? 1.0 : -1.0};
    q.points[2 + 4 * i] = centre + lift + (-half) * along;
    q.points[3 + 4 * i] = centre + lift + half * along;
  }
  rotate(q, rng);
  return q;
}

// The vertex falls onto the triangle's plane and ends `knob` above it, on it
// (contact at exactly t = 1) or `knob` below it.
CcdQueryPoints vf_contact_t1(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_triangle(q, rng);
  const double x = uniform(rng, 0.1, 0.4), y = uniform(rng, 0.1, 0.4);
  q.points[0] = {x, y, 1};
  q.points[4] = {x + uniform(rng, -0.05, 0.05), y + uniform(rng, -0.05, 0.05), random_sign_or_zero(rng) * knob};
  rotate(q, rng);
  return q;
}

// The vertex starts `knob` above the triangle's plane, on it (contact at
// exactly t = 0) or `knob` below it, and moves up away from it.
CcdQueryPoints vf_contact_t0(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_triangle(q, rng);
  const double x = uniform(rng, 0.1, 0.4), y = uniform(rng, 0.1, 0.4);
  q.points[0] = {x, y, random_sign_or_zero(rng) * knob};
  q.points[4] = {x + uniform(rng, -0.05, 0.05), y + uniform(rng, -0.05, 0.05), 1};
  rotate(q, rng);
  return q;
}

// The vertex slides across the triangle parallel to its plane, `knob` above
// it, on it (touching without crossing) or `knob` below it.
CcdQueryPoints vf_grazing(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_triangle(q, rng);
  const double z = random_sign_or_zero(rng) * knob, y = uniform(rng, 0.1, 0.4);
  q.points[0] = {-0.5, y, z};
  q.points[4] = {1.5, y + uniform(rng, -0.1, 0.1), z};
  tilt(q);  // not rotated: the touching case must stay exact
  return q;
}

// Edge b crosses over edge a parallel to the plane of both, `knob` above
// it, touching it or `knob` below it.
CcdQueryPoints ee_grazing(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_edge(q, rng);
  const double z = random_sign_or_zero(rng) * knob, x = uniform(rng, 0.2, 0.8);
  q.points[2] = {x, -1, z};
  q.points[3] = {x + uniform(rng, -0.2, 0.2), -0.5, z};
  q.points[6] = {x, 0.5, z};
  q.points[7] = {q.points[3].x, 1, z};
  tilt(q);  // not rotated: the touching case must stay exact
  return q;
}

// The vertex moves by `knob` only, across the triangle's plane or beside it
// (starting a fraction of the motion above or below).
CcdQueryPoints vf_tiny_motion(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_triangle(q, rng);
  const double x = uniform(rng, 0.1, 0.4), y = uniform(rng, 0.1, 0.4), start = uniform(rng, 0.1, 0.9) * knob;
  q.points[0] = {x, y, random_sign(rng) > 0 ? start : -start};
  q.points[4] = {x, y, q.points[0].z - knob};
  rotate(q, rng);
  return q;
}

// The vertex starts `knob` from the triangle's corner a (in a random
// direction) and moves away from the plane or through the triangle.
CcdQueryPoints vf_coincident(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_triangle(q, rng);
  const Vec3 direction{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
  q.points[0] = q.points[1] + knob * direction;
  q.points[4] = q.points[0] + Vec3{0.3, 0.3, random_sign(rng) * 0.5};
  rotate(q, rng);
  return q;
}

// Edge b starts parallel to edge a, `knob` above or below it, and moves
// away from it or through it (overlapping it at the moment of contact).
CcdQueryPoints ee_coincident(double knob, Rng& rng) {
  CcdQueryPoints q;
  static_edge(q, rng);
  const double side = random_sign(rng);
  const Vec3 offset{0, 0, side * knob}, move{0.1, 0, random_sign(rng) * 0.5};
  q.points[2] = q.points[0] + offset;
  q.points[3] = q.points[1] + offset;
  q.points[6] = q.points[2] + move;
  q.points[7] = q.points[3] + move;
  return q;  // not rotated: the overlap at contact stays exact
}

// A plain crossing near the edge of the triangle (the vertex passes 1e-3
// inside or outside it), for scaling and translating.
CcdQueryPoints vf_near_edge(Rng& rng) {
  CcdQueryPoints q;
  static_triangle(q, rng);
  const double x = uniform(rng, 0.2, 0.6), y = q.points[1].y + random_sign(rng) * 1e-3;
  q.points[0] = {x, y, 0.5};
  q.points[4] = {x, y, -0.5};
  rotate(q, rng);
  return q;
}

// Edge b passes 1e-3 beside edge a's end or just across it.
CcdQueryPoints ee_near_end(Rng& rng) {
  CcdQueryPoints q;
  static_edge(q, rng);
  const double x = q.points[1].x + random_sign(rng) * 1e-3;
  q.points[2] = {x, -0.5, 0.5};
  q.points[3] = {x, 0.5, 0.5};
  q.points[6] = {x, -0.5, -0.5};
  q.points[7] = {x, 0.5, -0.5};
  rotate(q, rng);
  return q;
}

CcdQueryPoints scaled(CcdQueryPoints q, double scale) {
  for (Vec3& p : q.points) p = scale * p;
  return q;
}

CcdQueryPoints translated(CcdQueryPoints q, double distance) {
  const Vec3 shift = (distance / std::sqrt(3.0)) * Vec3{1, 1, 1};
  for (Vec3& p : q.points) p = p + shift;
  return q;
}

CcdQueryPoints vf_scaled(double knob, Rng& rng) { return scaled(vf_near_edge(rng), knob); }
CcdQueryPoints ee_scaled(double knob, Rng& rng) { return scaled(ee_near_end(rng), knob); }
CcdQueryPoints vf_translated(double knob, Rng& rng) { return translated(vf_near_edge(rng), knob); }
CcdQueryPoints ee_translated(double knob, Rng& rng) { return translated(ee_near_end(rng), knob); }

std::vector<double> powers_of_ten(int from, int to) {
  std::vector<double> values;
  for (int e = from; e <= to; ++e) values.push_back(std::pow(10.0, e));
  return values;
}

struct FamilyDefinition {
  StabilityFamily family;
  Generator generate;
};

const std::vector<FamilyDefinition>& definitions() {
  static const std::vector<FamilyDefinition> all = {
      {{"vf-coplanar", false, "distance", "vertex and triangle in one plane for the whole step; the vertex stops "
                                          "the knob short of the triangle's edge or the knob past it",
        powers_of_ten(-15, -1)},
       vf_coplanar},
      {{"ee-coplanar", true, "distance", "both edges in one plane for the whole step; one edge's end stops the "
                                         "knob short of the other edge or the knob past it",
        powers_of_ten(-15, -1)},
       ee_coplanar},
      {{"ee-parallel", true, "angle", "edge b at the knob's angle (radians) to edge a passes through a's line, "
                                      "beside or across a: nearly parallel, collinear in the limit",
        powers_of_ten(-15, -1)},
       ee_parallel},
      {{"vf-contact-t0", false, "distance", "the vertex starts the knob above the plane, on it (contact at exactly "
                                            "t = 0) or the knob below it, and moves away",
        powers_of_ten(-15, -1)},
       vf_contact_t0},
      {{"vf-contact-t1", false, "distance", "the vertex falls onto the triangle and ends the knob above it, on it "
                                            "(contact at exactly t = 1) or the knob below it",
        powers_of_ten(-15, -1)},
       vf_contact_t1},
      {{"vf-grazing", false, "distance", "the vertex slides across the triangle parallel to it, the knob above, "
                                         "on it (touching without crossing) or the knob below",
        powers_of_ten(-15, -1)},
       vf_grazing},
      {{"ee-grazing", true, "distance", "edge b crosses over edge a parallel to both, the knob above, touching "
                                        "or the knob below",
        powers_of_ten(-15, -1)},
       ee_grazing},
      {{"vf-tiny-motion", false, "motion", "the vertex moves by the knob only, across the triangle or beside it",
        powers_of_ten(-15, -1)},
       vf_tiny_motion},
      {{"vf-coincident", false, "distance", "the vertex starts the knob from a corner of the triangle (0: on it) "
                                            "and moves away or through",
        powers_of_ten(-15, -1)},
       vf_coincident},
      {{"ee-coincident", true, "distance", "edge b starts parallel to edge a, the knob above or below it, and moves "
                                           "away or through it",
        powers_of_ten(-15, -1)},
       ee_coincident},
      {{"vf-scaled", false, "scale", "a crossing 1e-3 inside or outside the triangle's edge, scaled by the knob",
        powers_of_ten(-6, 6)},
       vf_scaled},
      {{"ee-scaled", true, "scale", "edge b passes 1e-3 beside or across edge a's end, scaled by the knob",
        powers_of_ten(-6, 6)},
       ee_scaled},
      {{"vf-translated", false, "distance", "the scaled family's crossing at size 1, moved the knob from the origin",
        powers_of_ten(0, 12)},
       vf_translated},
      {{"ee-translated", true, "distance", "the edge-edge crossing at size 1, moved the knob from the origin",
        powers_of_ten(0, 12)},
       ee_translated},
  };
  return all;
}

}  // namespace

std::vector<StabilityFamily> stability_families() {
  std::vector<StabilityFamily> families;
  for (const FamilyDefinition& definition : definitions()) families.push_back(definition.family);
  return families;
}

std::vector<LabelledQuery> family_queries(const StabilityFamily& family, double knob, int samples,
                                          std::uint64_t seed) {
  for (const FamilyDefinition& definition : definitions()) {
    if (definition.family.name != family.name) continue;
    Rng rng(seed);
    std::vector<LabelledQuery> queries;
    for (int i = 0; i < samples; ++i) {
      LabelledQuery q;
      q.query = definition.generate(knob, rng);
      q.query.edge_edge = definition.family.edge_edge;
      q.truth = exact_collides(q.query);
      queries.push_back(q);
    }
    return queries;
  }
  throw UsageError("no stability family named " + family.name);
}

}  // namespace snag::bench
