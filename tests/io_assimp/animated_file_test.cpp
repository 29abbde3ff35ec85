// open_animated_file on hand-made glTF 2.0 files whose answers are known in
// closed form: node translation keys under a static parent, morph targets with
// animated weights, and a two-bone skin with a rotating joint.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gltf_builder.hpp"
#include "io/assimp_reader.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {
namespace {

using test::GltfBuilder;
constexpr double kTol = 1e-12;
const double kPi = std::acos(-1.0);

void expect_near(Vec3 got, Vec3 want, const std::string& what) {
  EXPECT_NEAR(got.x, want.x, kTol) << what;
  EXPECT_NEAR(got.y, want.y, kTol) << what;
  EXPECT_NEAR(got.z, want.z, kTol) << what;
}

/// A triangle (0,0,0) (1,0,0) (0,1,0) in node "mover" (child of "base" at z = 5)
/// whose translation keys are (0,0,0) at 0 s, (2,0,0) at 1 s, (2,4,-1) at 2 s.
std::string write_translation_file() {
  GltfBuilder b;
  const int pos = b.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int ids = b.add_indices({0, 1, 2});
  const int times = b.add_scalars({0, 1, 2}, true);
  const int values = b.add_vec3({0, 0, 0, 2, 0, 0, 2, 4, -1}, false);
  auto& d = b.doc();
  d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ids}}}}}};
  d["nodes"] = {{{"name", "base"}, {"translation", {0, 0, 5}}, {"children", {1}}}, {{"name", "mover"}, {"mesh", 0}}};
  d["scenes"] = {{{"nodes", {0}}}};
  d["scene"] = 0;
  d["animations"] = {{{"samplers", {{{"input", times}, {"output", values}, {"interpolation", "LINEAR"}}}},
                      {"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}}}}}};
  const std::string path = test::scratch_dir("translation") + "/mover.gltf";
  b.write(path);
  return path;
}

Vec3 analytic_translation(double t) {
  if (t <= 1) return {2 * t, 0, 0};
  const double s = std::min(t, 2.0) - 1;
  return {2, 4 * s, -s};
}

TEST(AnimatedGltf, NodeTranslationMatchesLinearKeysAtEverySample) {
  InputSpec input{write_translation_file(), "", ""};
  const auto source = open_animated_file(input, CacheOptions{});
  ASSERT_EQ(source->scene().objects().size(), 1u);
  EXPECT_EQ(source->scene().objects()[0].name, "mover");
  EXPECT_EQ(source->scene().vertex_count(), 3u);
  ASSERT_EQ(source->frame_count(), 49u);  // 0 s to 2 s at the default 24 per second
  const Vec3 rest[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<Vec3> p;
  for (std::size_t i = 0; i < source->frame_count(); ++i) {
    source->read_frame(i, p);
    ASSERT_EQ(p.size(), 3u);
    const double t = static_cast<double>(i) / 24.0;
    EXPECT_NEAR(source->frame_time(i), static_cast<double>(i), kTol);
    for (int v = 0; v < 3; ++v)
      expect_near(p[v], rest[v] + analytic_translation(t) + Vec3{0, 0, 5}, "frame " + std::to_string(i));
  }
}

TEST(AnimatedGltf, HonoursSampleRateAndTimeRange) {
  InputSpec input{write_translation_file(), "", ""};
  CacheOptions options;
  options.sample_rate = 4.0;
  options.start_time = 0.5;
  options.end_time = 1.5;
  const auto source = open_animated_file(input, options);
  ASSERT_EQ(source->frame_count(), 5u);  // 0.5, 0.75, 1, 1.25, 1.5 s
  std::vector<Vec3> p;
  for (std::size_t i = 0; i < 5; ++i) {
    source->read_frame(i, p);
    const double t = 0.5 + 0.25 * static_cast<double>(i);
    expect_near(p[1], Vec3{1, 0, 5} + analytic_translation(t), "sample " + std::to_string(i));
  }
  EXPECT_THROW(source->read_frame(5, p), InputError);
}

TEST(AnimatedGltf, RejectsNonPositiveSampleRate) {
  InputSpec input{write_translation_file(), "", ""};
  CacheOptions options;
  options.sample_rate = 0.0;
  EXPECT_THROW(open_animated_file(input, options), UsageError);
}

TEST(AnimatedGltf, MorphTargetsFollowAnimatedWeights) {
  GltfBuilder b;
  const int pos = b.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int d0 = b.add_vec3({0, 0, 1, 0, 0, 2, 0, 0, 3});
  const int d1 = b.add_vec3({1, 0, 0, 1, 0, 0, 1, 0, 0});
  const int ids = b.add_indices({0, 1, 2});
  const int times = b.add_scalars({0, 1}, true);
  const int weights = b.add_scalars({0, 0.5f, 1, 0});  // key 0: (0, 0.5), key 1: (1, 0)
  auto& d = b.doc();
  d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}},
                                   {"indices", ids},
                                   {"targets", {{{"POSITION", d0}}, {{"POSITION", d1}}}}}}},
                  {"weights", {0, 0}}}};
  d["nodes"] = {{{"name", "blob"}, {"mesh", 0}}};
  d["scenes"] = {{{"nodes", {0}}}};
  d["scene"] = 0;
  d["animations"] = {{{"samplers", {{{"input", times}, {"output", weights}, {"interpolation", "LINEAR"}}}},
                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}};
  const std::string path = test::scratch_dir("morph") + "/blob.gltf";
  b.write(path);

  const auto source = open_animated_file(InputSpec{path, "", ""}, CacheOptions{});
  ASSERT_EQ(source->frame_count(), 25u);
  const Vec3 rest[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Vec3 delta0[3] = {{0, 0, 1}, {0, 0, 2}, {0, 0, 3}};
  std::vector<Vec3> p;
  for (std::size_t i = 0; i < source->frame_count(); ++i) {
    source->read_frame(i, p);
    const double t = static_cast<double>(i) / 24.0;
    const double w0 = t, w1 = 0.5 * (1 - t);
    for (int v = 0; v < 3; ++v)
      expect_near(p[v], rest[v] + w0 * delta0[v] + w1 * Vec3{1, 0, 0}, "frame " + std::to_string(i));
  }
}

/// Two joints: "root_bone" at the origin and "tip_bone" at (0,1,0) rotating
/// about Z from 0 to 180 degrees over 1 s (slerp: angle = pi t). The skinned
/// node's own translation (10,0,0) must be ignored (glTF 2.0, skins).
TEST(AnimatedGltf, TwoBoneSkinMatchesHandComputedLinearBlend) {
  GltfBuilder b;
  const int pos = b.add_vec3({0, 0, 0, 1, 1, 0, 0, 2, 0, 1, 2, 0});
  const int joints = b.add_joints({0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
  const int weights = b.add_vec4({1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
  const int ids = b.add_indices({0, 1, 2, 1, 3, 2});
  const int ibm = b.add_mat4({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                              1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1});
  const int times = b.add_scalars({0, 1}, true);
  const int rotations = b.add_vec4({0, 0, 0, 1, 0, 0, 1, 0});
  auto& d = b.doc();
  d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}},
                                   {"indices", ids}}}}}};
  d["skins"] = {{{"joints", {1, 2}}, {"inverseBindMatrices", ibm}}};
  d["nodes"] = {{{"name", "skinned"}, {"mesh", 0}, {"skin", 0}, {"translation", {10, 0, 0}}},
                {{"name", "root_bone"}, {"children", {2}}},
                {{"name", "tip_bone"}, {"translation", {0, 1, 0}}}};
  d["scenes"] = {{{"nodes", {0, 1}}}};
  d["scene"] = 0;
  d["animations"] = {{{"samplers", {{{"input", times}, {"output", rotations}, {"interpolation", "LINEAR"}}}},
                      {"channels", {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}}}}}};
  const std::string path = test::scratch_dir("skin") + "/skinned.gltf";
  b.write(path);

  const auto source = open_animated_file(InputSpec{path, "", ""}, CacheOptions{});
  ASSERT_EQ(source->scene().objects().size(), 1u);
  EXPECT_EQ(source->scene().objects()[0].name, "skinned");
  ASSERT_EQ(source->frame_count(), 25u);
  std::vector<Vec3> p;
  for (std::size_t i = 0; i < source->frame_count(); ++i) {
    source->read_frame(i, p);
    ASSERT_EQ(p.size(), 4u);
    const double angle = kPi * static_cast<double>(i) / 24.0;
    const double c = std::cos(angle), s = std::sin(angle);
    const std::string what = "frame " + std::to_string(i);
    expect_near(p[0], {0, 0, 0}, what);
    expect_near(p[1], 0.5 * (Vec3{1, 1, 0} + Vec3{c, 1 + s, 0}), what);
    expect_near(p[2], {-s, 1 + c, 0}, what);
    expect_near(p[3], {c - s, 1 + s + c, 0}, what);
  }
}

}  // namespace
}  // namespace snag::io
