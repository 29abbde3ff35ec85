#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <limits>

#include "io/mdd_reader.hpp"
#include "io/open_cache.hpp"
#include "io/pc2_reader.hpp"
#include "test_files.hpp"

namespace snag::io {
namespace {

using testing::expect_input_error;
using testing::put;

/// Point p of frame f: distinct float32 values that are not round decimals.
float coordinate(int frame, int point, int axis) { return 0.1f * static_cast<float>(frame + 1) + 1.3f * point + 0.7f * axis; }

std::string pc2(int points, int frames, float start = 10, float rate = 0.5f) {
  std::string bytes("POINTCACHE2", 12);
  put<std::int32_t>(bytes, 1);
  put<std::int32_t>(bytes, points);
  put<float>(bytes, start);
  put<float>(bytes, rate);
  put<std::int32_t>(bytes, frames);
  for (int f = 0; f < frames; ++f) {
    for (int p = 0; p < points; ++p) {
      for (int axis = 0; axis < 3; ++axis) put<float>(bytes, coordinate(f, p, axis));
    }
  }
  return bytes;
}

std::string mdd(int points, int frames, bool rest_frame) {
  std::string bytes;
  put<std::int32_t>(bytes, frames, true);
  put<std::int32_t>(bytes, points, true);
  for (int f = 0; f < frames; ++f) put<float>(bytes, 0.25f + f / 24.0f, true);
  if (rest_frame) {
    for (int k = 0; k < points * 3; ++k) put<float>(bytes, -99.0f, true);
  }
  for (int f = 0; f < frames; ++f) {
    for (int p = 0; p < points; ++p) {
      for (int axis = 0; axis < 3; ++axis) put<float>(bytes, coordinate(f, p, axis), true);
    }
  }
  return bytes;
}

const char* kQuadObj = "o Sheet\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

void expect_frames(const FrameSource& source, int frames) {
  ASSERT_EQ(source.frame_count(), static_cast<std::size_t>(frames));
  ASSERT_EQ(source.scene().vertex_count(), 4u);
  EXPECT_EQ(source.scene().triangle_count(), 2u);
  std::vector<Vec3> positions;
  for (int f = 0; f < frames; ++f) {
    source.read_frame(f, positions);
    ASSERT_EQ(positions.size(), 4u);
    for (int p = 0; p < 4; ++p) {
      for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(positions[p][axis], static_cast<double>(coordinate(f, p, axis)));
    }
  }
}

TEST(PointCache, ReadsPc2OnTopology) {
  testing::TempDir dir;
  CacheOptions options;
  options.inputs.push_back({dir.write("cloth.pc2", pc2(4, 3)), dir.write("cloth.obj", kQuadObj), ""});
  const auto source = open_cache(options);
  expect_frames(*source, 3);
  EXPECT_EQ(source->frame_time(0), 10.0);
  EXPECT_EQ(source->frame_time(2), 11.0);
  EXPECT_EQ(source->scene().objects()[0].name, "Sheet");
}

TEST(PointCache, ReadsMddInBothLayouts) {
  for (bool rest_frame : {false, true}) {
    testing::TempDir dir;
    CacheOptions options;
    options.inputs.push_back({dir.write("cloth.mdd", mdd(4, 3, rest_frame)), dir.write("cloth.obj", kQuadObj), "cloth"});
    const auto source = open_cache(options);
    expect_frames(*source, 3);
    EXPECT_EQ(source->frame_time(2), static_cast<double>(0.25f + 2 / 24.0f));
    EXPECT_EQ(source->scene().objects()[0].name, "cloth");
  }
}

TEST(PointCache, GathersObjectVerticesOfAMultiObjectTopology) {
  testing::TempDir dir;
  // Vertex 2 is used by no face, so the objects hold file vertices {0,1,3} and {4,5,6}.
  const std::string topology = "o A\nv 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\no B\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 1 2 4\nf 5 6 7\n";
  CacheOptions options;
  options.inputs.push_back({dir.write("c.pc2", pc2(7, 2)), dir.write("t.obj", topology), ""});
  const auto source = open_cache(options);
  ASSERT_EQ(source->scene().vertex_count(), 6u);
  std::vector<Vec3> positions;
  source->read_frame(1, positions);
  const int file_vertex[6] = {0, 1, 3, 4, 5, 6};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(positions[k].x, static_cast<double>(coordinate(1, file_vertex[k], 0)));
}

/// The resident size, in KiB, of this process's mappings of `path` (smaps).
std::size_t resident_kib_of(const std::string& path) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  std::size_t kib = 0;
  while (std::getline(smaps, line)) {
    if (!line.empty() && std::isxdigit(static_cast<unsigned char>(line[0])) && line.find('-') < line.find(' ')) {
      inside = line.size() >= path.size() && line.compare(line.size() - path.size(), path.size(), path) == 0;
    } else if (inside && line.rfind("Rss:", 0) == 0) {
      kib += std::stoul(line.substr(4));
    }
  }
  return kib;
}

// A long cache read frame after frame keeps a flat resident size: each
// frame's pages leave the process once read (they stay in the page cache).
TEST(PointCache, ReadingEveryFrameLeavesFewPagesResident) {
  const int points = 10007, frames = 300;  // 120 KB frames, not page-aligned: 36 MB
  testing::TempDir dir;
  std::string obj = "o Cloud\n";
  for (int p = 0; p < points; ++p) obj += "v 0 0 0\n";
  for (int p = 1; p + 2 <= points; p += 3) obj += "f " + std::to_string(p) + " " + std::to_string(p + 1) + " " + std::to_string(p + 2) + "\n";
  obj += "f " + std::to_string(points - 2) + " " + std::to_string(points - 1) + " " + std::to_string(points) + "\n";
  CacheOptions options;
  const std::string cache = dir.write("long.pc2", pc2(points, frames));
  options.inputs.push_back({cache, dir.write("long.obj", obj), ""});
  const auto source = open_cache(options);
  std::vector<Vec3> positions;
  std::size_t largest = 0;
  for (int f = 0; f < frames; ++f) {
    source->read_frame(f, positions);
    ASSERT_EQ(positions.size(), static_cast<std::size_t>(points));
    ASSERT_EQ(positions[points - 1].x, coordinate(f, points - 1, 0));
    largest = std::max(largest, resident_kib_of(cache));
  }
  EXPECT_LT(largest, 1024u) << "KiB of the 36 MB cache resident at once";
}

TEST(PointCache, RejectsTruncatedPc2) {
  std::string bytes = pc2(4, 3);
  bytes.resize(bytes.size() - 1);
  expect_input_error([&] { parse_pc2_layout(bytes, "t.pc2"); }, "header says 3 samples of 4 points (176 bytes) but the file has 175 bytes");
  expect_input_error([] { parse_pc2_layout(std::string("POINTCACHE2", 12), "t.pc2"); }, "truncated");
}

TEST(PointCache, RejectsPc2CountsLargerThanTheFile) {
  expect_input_error([] { parse_pc2_layout(pc2(4, 3).replace(16, 4, std::string("\xff\xff\xff\x7f", 4)), "big.pc2"); },
                     "header says 3 samples of 2,147,483,647 points");
  expect_input_error([] { parse_pc2_layout(pc2(4, 3).replace(28, 4, std::string("\xff\xff\xff\xff", 4)), "neg.pc2"); },
                     "sample count -1");
}

TEST(PointCache, RejectsBadPc2Header) {
  expect_input_error([] { parse_pc2_layout(pc2(4, 3).replace(0, 5, "XOINT"), "m.pc2"); }, "m.pc2: byte 0: not a PC2 file");
  expect_input_error([] { parse_pc2_layout(pc2(4, 3, 0, 0), "r.pc2"); }, "sample rate");
}

TEST(PointCache, RejectsMddSizeThatFitsNeitherLayout) {
  std::string bytes = mdd(4, 3, false);
  bytes += "xy";
  expect_input_error([&] { parse_mdd_layout(bytes, "t.mdd"); }, "header says 3 frames of 4 points (164 bytes, or 212 with a rest frame)");
  expect_input_error([] { parse_mdd_layout(mdd(4, 3, false).replace(0, 4, std::string("\x7f\xff\xff\xff", 4)), "big.mdd"); },
                     "header says 2,147,483,647 frames");
}

TEST(PointCache, RejectsNonFinitePoints) {
  testing::TempDir dir;
  std::string bytes = pc2(4, 3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&bytes[32 + 48 + 12 * 2 + 4], &nan, 4);  // frame 1, point 2, y
  CacheOptions options;
  options.inputs.push_back({dir.write("n.pc2", bytes), dir.write("n.obj", kQuadObj), ""});
  const auto source = open_cache(options);
  std::vector<Vec3> positions;
  source->read_frame(0, positions);
  expect_input_error([&] { source->read_frame(1, positions); }, "n.pc2: frame 1: byte 104: point 2: coordinate is not finite");
}

TEST(PointCache, RejectsPointCountThatDiffersFromTopology) {
  testing::TempDir dir;
  CacheOptions options;
  options.inputs.push_back({dir.write("c.pc2", pc2(5, 2)), dir.write("t.obj", kQuadObj), ""});
  expect_input_error([&] { open_cache(options); }, "c.pc2: 5 points, but the topology mesh");
}

}  // namespace
}  // namespace snag::io
