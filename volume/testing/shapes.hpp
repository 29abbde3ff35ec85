// Closed and open test shapes with known measures, for the tests and the
// benchmark of snag::volume: boxes, icospheres, square sheets, and real
// meshes read from files.
#pragma once

#include <string>

#include "volume/triangle_mesh.hpp"

namespace snag::volume::testing {

/// The closed box [lo, hi], 12 triangles, faces counter-clockwise from outside.
TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi);
/// A closed icosphere: the icosahedron subdivided `levels` times (20 * 4^levels
/// triangles), vertices on the sphere, faces counter-clockwise from outside.
TriangleMesh icosphere(const Vec3& centre, double radius, int levels);
/// An open square sheet in the plane z = centre.z, side `side`, n x n squares
/// of two triangles each.
TriangleMesh sheet(const Vec3& centre, double side, int n);
/// `mesh` rotated by 90 degrees about the x axis through `centre` (y -> z, z -> -y).
TriangleMesh turned_about_x(const TriangleMesh& mesh, const Vec3& centre);
/// Both meshes as one (b's vertex ids after a's).
TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b);
/// `mesh` moved by `offset`.
TriangleMesh moved(const TriangleMesh& mesh, const Vec3& offset);
/// The first object of a mesh file (OBJ, PLY, STL; snag's readers). Throws InputError.
TriangleMesh read_first_object(const std::string& path);

}  // namespace snag::volume::testing
