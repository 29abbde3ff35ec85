// read_mesh_with_assimp: node transforms applied at rest, vertex order kept,
// objects named after mesh nodes (made unique).
#include <vector>

#include <gtest/gtest.h>

#include "gltf_builder.hpp"
#include "io/assimp_reader.hpp"

namespace snag::io {
namespace {

/// One quad (two triangles) placed by node "a" (translation (1,2,3), scale 2),
/// by its child "b" (translation (0,0,1)) and by a second root node also named "a".
std::string write_static_file() {
  test::GltfBuilder b;
  const int pos = b.add_vec3({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  const int ids = b.add_indices({0, 1, 2, 0, 2, 3});
  auto& d = b.doc();
  d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ids}}}}}};
  d["nodes"] = {{{"name", "a"}, {"mesh", 0}, {"translation", {1, 2, 3}}, {"scale", {2, 2, 2}}, {"children", {1}}},
                {{"name", "b"}, {"mesh", 0}, {"translation", {0, 0, 1}}},
                {{"name", "a"}, {"mesh", 0}}};
  d["scenes"] = {{{"nodes", {0, 2}}}};
  d["scene"] = 0;
  const std::string path = test::scratch_dir("static") + "/quads.gltf";
  b.write(path);
  return path;
}

TEST(StaticAssimpMesh, AppliesNodeTransformsAndKeepsVertexOrder) {
  const MeshData data = read_mesh_with_assimp(write_static_file());
  ASSERT_EQ(data.objects.size(), 3u);
  EXPECT_EQ(data.objects[0].name, "a");
  EXPECT_EQ(data.objects[1].name, "b");
  EXPECT_EQ(data.objects[2].name, "a.1");
  ASSERT_EQ(data.positions.size(), 12u);
  const Vec3 quad[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (int v = 0; v < 4; ++v) {
    EXPECT_EQ(data.positions[v], (2.0 * quad[v] + Vec3{1, 2, 3}));
    EXPECT_EQ(data.positions[4 + v], (2.0 * (quad[v] + Vec3{0, 0, 1}) + Vec3{1, 2, 3}));
    EXPECT_EQ(data.positions[8 + v], quad[v]);
  }
  for (std::size_t o = 0; o < 3; ++o) {
    const MeshObject& object = data.objects[o];
    EXPECT_EQ(object.vertices, (std::vector<Index>{Index(4 * o), Index(4 * o + 1), Index(4 * o + 2), Index(4 * o + 3)}));
    EXPECT_EQ(object.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));
  }
}

TEST(StaticAssimpMesh, FileWithoutAnimationIsOneFrame) {
  const auto source = open_animated_file(InputSpec{write_static_file(), "", ""}, CacheOptions{});
  ASSERT_EQ(source->frame_count(), 1u);
  EXPECT_EQ(source->scene().objects().size(), 3u);
  EXPECT_EQ(source->scene().triangle_count(), 6u);
  std::vector<Vec3> p;
  source->read_frame(0, p);
  const MeshData data = read_mesh_with_assimp(write_static_file());
  EXPECT_EQ(p, data.positions);
}

TEST(StaticAssimpMesh, InputNameOverridesObjectNames) {
  const auto source = open_animated_file(InputSpec{write_static_file(), "", "prop"}, CacheOptions{});
  ASSERT_EQ(source->scene().objects().size(), 3u);
  EXPECT_EQ(source->scene().objects()[0].name, "prop.a");
  EXPECT_EQ(source->scene().objects()[2].name, "prop.a.1");
}

}  // namespace
}  // namespace snag::io
