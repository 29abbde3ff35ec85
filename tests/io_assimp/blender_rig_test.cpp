// One rig exported from Blender (export_rig.py) as glTF, FBX and Collada: the
// three must give the same positions as each other and as Blender's own
// evaluated positions (rig_positions.csv) at frames 0, 6, 12, 18, 24.
//
// Tolerance 1e-5 m: every format stores float32 (relative rounding 6e-8) and
// the pose goes through about four chained float32 transforms on coordinates
// below 2.5 m, so honest errors are of order 1e-6; the smallest motion between
// two compared frames (6 frames of the 1 m/s slide, 0.25 m) is 25000 times
// larger, so a wrong time or a missed transform cannot pass.
//
// FBX and Collada come back from assimp with one vertex per triangle corner
// (108) where glTF keeps Blender's 20, so positions are compared as sets:
// every vertex of one side lies within the tolerance of some vertex of the other.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "io/assimp_reader.hpp"

namespace snag::io {
namespace {

constexpr double kTol = 1e-5;
const std::string kData = std::string(SNAG_SOURCE_DIR) + "/tests/io_assimp/data/";

/// Blender's positions per frame, converted from Blender's Z-up to the
/// Y-up frame every exporter writes: (x, y, z) -> (x, z, -y).
std::map<int, std::vector<Vec3>> blender_positions() {
  std::ifstream in(kData + "rig_positions.csv");
  std::string line;
  std::getline(in, line);  // header
  std::map<int, std::vector<Vec3>> frames;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string field[6];
    for (auto& f : field) std::getline(row, f, ',');
    const Vec3 p{std::stod(field[3]), std::stod(field[4]), std::stod(field[5])};
    frames[std::stoi(field[0])].push_back({p.x, p.z, -p.y});
  }
  return frames;
}

/// Largest distance from a point of `a` to its nearest point of `b`.
double one_sided_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double worst = 0;
  for (const Vec3& p : a) {
    double best = INFINITY;
    for (const Vec3& q : b) best = std::min(best, std::sqrt(squared_norm(p - q)));
    worst = std::max(worst, best);
  }
  return worst;
}

double set_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return std::max(one_sided_distance(a, b), one_sided_distance(b, a));
}

std::map<int, std::vector<Vec3>> read_rig(const std::string& file) {
  const auto source = open_animated_file(InputSpec{kData + file, "", ""}, CacheOptions{});
  EXPECT_EQ(source->frame_count(), 25u) << file;
  EXPECT_EQ(source->scene().objects().size(), 1u) << file;
  EXPECT_EQ(source->scene().triangle_count(), 36u) << file;
  std::map<int, std::vector<Vec3>> frames;
  for (int frame : {0, 6, 12, 18, 24}) source->read_frame(frame, frames[frame]);
  return frames;
}

TEST(BlenderRig, BlenderCsvHasTheComparedFrames) {
  const auto blender = blender_positions();
  ASSERT_EQ(blender.size(), 5u);
  for (const auto& [frame, p] : blender) EXPECT_EQ(p.size(), 20u) << frame;
  // The rig really moves: the tip ring differs between the first and last frame.
  EXPECT_GT(set_distance(blender.at(0), blender.at(24)), 0.5);
}

class BlenderRigFormat : public ::testing::TestWithParam<const char*> {};

TEST_P(BlenderRigFormat, MatchesBlenderEvaluatedPositions) {
  const auto blender = blender_positions();
  const auto frames = read_rig(GetParam());
  for (const auto& [frame, p] : frames) {
    EXPECT_LT(set_distance(p, blender.at(frame)), kTol) << GetParam() << " frame " << frame;
    if (frame > 0) EXPECT_GT(set_distance(p, blender.at(frame - 6)), 0.2) << GetParam() << " frame " << frame;
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, BlenderRigFormat, ::testing::Values("rig.glb", "rig.fbx", "rig.dae"));

TEST(BlenderRig, GltfFbxAndColladaAgree) {
  const auto gltf = read_rig("rig.glb");
  const auto fbx = read_rig("rig.fbx");
  const auto dae = read_rig("rig.dae");
  for (int frame : {0, 6, 12, 18, 24}) {
    EXPECT_LT(set_distance(gltf.at(frame), fbx.at(frame)), kTol) << "frame " << frame;
    EXPECT_LT(set_distance(gltf.at(frame), dae.at(frame)), kTol) << "frame " << frame;
  }
}

}  // namespace
}  // namespace snag::io
