// WindingColumns against the generalized winding number (the solid angles of
// the triangles summed, van Oosterom and Strackee 1983) on points of a
// lattice, lines through vertices and edges included.
#include <gtest/gtest.h>

#include <cmath>

#include "volume/testing/shapes.hpp"
#include "volume/winding_columns.hpp"

namespace {

using namespace snag::volume;
using snag::Vec3;
namespace vt = snag::volume::testing;

// The winding number by solid angles: exact up to rounding away from the surface.
double solid_angle_winding(const TriangleMesh& mesh, const Vec3& p) {
  double sum = 0;
  for (const snag::Triangle& f : mesh.triangles) {
    const Vec3 a = mesh.vertices[f[0]] - p, b = mesh.vertices[f[1]] - p, c = mesh.vertices[f[2]] - p;
    const double la = std::sqrt(squared_norm(a)), lb = std::sqrt(squared_norm(b)), lc = std::sqrt(squared_norm(c));
    const double numerator = dot(a, cross(b, c));
    const double denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    sum += 2 * std::atan2(numerator, denominator);
  }
  return sum / (4 * M_PI);
}

// Whether p lies in the plane of a triangle, within its box: on the surface,
// or too near it for the solid angles to be a number.
bool near_a_face_plane(const TriangleMesh& mesh, const Vec3& p) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const snag::Triangle& f = mesh.triangles[t];
    const Vec3 a = mesh.vertices[f[0]] - p, b = mesh.vertices[f[1]] - p, c = mesh.vertices[f[2]] - p;
    if (std::abs(dot(a, cross(b, c))) < 1e-12 && overlaps(grown(triangle_box(mesh, t), 1e-9), {p, p})) return true;
  }
  return false;
}

void expect_matches_solid_angles(const TriangleMesh& mesh, double step) {
  const Box box = grown(mesh_box(mesh), 2 * step);
  const WindingColumns winding(mesh, box);
  int checked = 0, inside = 0;
  for (double z = box.lo.z; z <= box.hi.z; z += step) {
    for (double y = box.lo.y; y <= box.hi.y; y += step) {
      for (double x = box.lo.x + step / 3; x <= box.hi.x; x += step) {
        const Vec3 p{x, y, z};
        if (near_a_face_plane(mesh, p)) continue;
        const double expected = solid_angle_winding(mesh, p);
        if (std::abs(expected - std::round(expected)) > 1e-6) continue;  // on the surface
        const int w = winding.winding_number(p);
        ASSERT_EQ(w, std::lround(expected)) << p.x << " " << p.y << " " << p.z;
        ++checked;
        inside += w > 0;
      }
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(inside, 20);
}

TEST(WindingColumns, MatchesSolidAnglesOnTwoOverlappingBoxesThroughTheirEdges) {
  // Lines at y, z multiples of 0.25 run along the boxes' edges and faces.
  const TriangleMesh mesh = vt::joined(vt::box_mesh({0, 0, 0}, {1, 1, 1}),
                                            vt::box_mesh({0.5, 0.5, 0.25}, {1.5, 1.25, 1.5}));
  expect_matches_solid_angles(mesh, 0.125);
}

TEST(WindingColumns, MatchesSolidAnglesOnASphereAndAnInsideOutOne) {
  const TriangleMesh sphere = vt::icosphere({0.1, 0.2, 0.3}, 1, 2);
  expect_matches_solid_angles(sphere, 0.1);
  TriangleMesh flipped = sphere;
  for (snag::Triangle& f : flipped.triangles) std::swap(f[1], f[2]);
  // Inside-out: the solid angles give -1 inside; the columns take the mesh's orientation.
  const WindingColumns winding(flipped, grown(mesh_box(flipped), 0.1));
  EXPECT_EQ(winding.winding_number({0.1, 0.2, 0.3}), 1);
  EXPECT_EQ(winding.winding_number({2, 0.2, 0.3}), 0);
}

TEST(WindingColumns, LengthWithWindingCutsIntervalsAtTheEnds) {
  // Winding 1 on [0, 3], 2 on [1, 2].
  const std::vector<Crossing> line = {{0, -1}, {1, -1}, {2, 1}, {3, 1}};
  EXPECT_DOUBLE_EQ(length_with_winding(line, -5, 5, 1), 3);
  EXPECT_DOUBLE_EQ(length_with_winding(line, -5, 5, 2), 1);
  EXPECT_DOUBLE_EQ(length_with_winding(line, 1.5, 2.5, 2), 0.5);
  EXPECT_DOUBLE_EQ(length_with_winding(line, 0.5, 2.5, 1), 2);
  EXPECT_DOUBLE_EQ(length_with_winding(line, 3.5, 4, 1), 0);
  EXPECT_EQ(winding_at(line, 1.5), 2);
  EXPECT_EQ(winding_at(line, -1), 0);
}

}  // namespace
