// snag-volume's region measures in a report: written by ReportWriter and read
// back by ReportReader field for field, each measure with its own fields;
// regions without measures read back without them; an unknown measure or a
// missing field is rejected with the line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "libcd/core/error.hpp"
#include "report/report_reader.hpp"
#include "report/report_writer.hpp"

namespace {

using snag::report::RegionMeasures;
using snag::report::RegionRecord;
using snag::report::ReportReader;
using Record = ReportReader::Record;

snag::report::Header two_objects() {
  snag::report::Header header;
  header.tool = "snag-volume";
  header.source = "a.obj + b.obj";
  header.objects.resize(2);
  header.objects[0].name = "cloth";
  header.objects[0].triangles = 10;
  header.objects[0].vertices = 12;
  header.objects[0].file_vertices = 12;
  header.objects[1].name = "body";
  header.objects[1].triangles = 20;
  header.objects[1].vertices = 12;
  header.objects[1].file_vertices = 12;
  header.frame_count = 1;
  return header;
}

RegionRecord region(std::size_t id, std::size_t a, std::size_t b) {
  RegionRecord r;
  r.id = id;
  r.object_a = a;
  r.object_b = b;
  r.frame = 4;
  r.track = id;
  r.events = 1;
  r.faces_a = {1};
  if (a != b) r.faces_b = {2};
  r.face_count = r.faces_a.size() + r.faces_b.size();
  r.bounds = {{0, 0, 0}, {1, 1, 1}};
  r.centroid = {0.5, 0.5, 0.5};
  return r;
}

// Writes the header, frame 4 with `regions`, and a trailer to `path`.
void write_report(const std::string& path, const std::vector<RegionRecord>& regions) {
  std::ofstream out(path);
  snag::report::ReportWriter writer(out);
  writer.write_header(two_objects());
  snag::report::FrameRecord frame;
  frame.index = 4;
  frame.regions = regions.size();
  writer.write_frame(frame);
  for (const RegionRecord& r : regions) writer.write_region(r);
  snag::report::Trailer trailer;
  trailer.frames = 1;
  trailer.allow_counts = {};
  writer.write_trailer(trailer);
  writer.flush();
}

class RegionMeasuresTest : public ::testing::Test {
 protected:
  RegionMeasuresTest()
      : dir_(std::filesystem::temp_directory_path() / ("snag_region_measures_" + std::to_string(getpid()))) {
    std::filesystem::create_directories(dir_);
  }
  ~RegionMeasuresTest() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::filesystem::path dir_;
};

TEST_F(RegionMeasuresTest, EachMeasureReadsBackAsWritten) {
  RegionRecord overlap = region(0, 1, 1);
  overlap.measures = RegionMeasures{};
  overlap.measures->measure = "self_overlap_volume";
  overlap.measures->reason = "body is closed";
  overlap.measures->voxel_size = 0.125;
  overlap.measures->volume = 1.5e-3;
  overlap.measures->volume_error = 2.5e-5;
  RegionRecord penetration = region(1, 0, 1);
  penetration.measures = RegionMeasures{};
  penetration.measures->measure = "penetration";
  penetration.measures->reason = "cloth is open (8 boundary edges), body is closed";
  penetration.measures->voxel_size = 0.01;
  penetration.measures->depth = 0.0375;
  penetration.measures->depth_error = 0.001;
  penetration.measures->area = 0.75;
  penetration.measures->area_error = 0.0625;
  RegionRecord curve = region(2, 0, 0);
  curve.measures = RegionMeasures{};
  curve.measures->measure = "curve_length";
  curve.measures->reason = "cloth is open \"quoted\"";
  curve.measures->curve_length = 3.25;
  curve.measures->segments = 17;
  RegionRecord plain = region(3, 0, 1);

  const std::string file = path("measures.jsonl");
  write_report(file, {overlap, penetration, curve, plain});
  ReportReader reader(file);
  ASSERT_EQ(reader.next(), Record::kFrame);
  for (const RegionRecord& expected : {overlap, penetration, curve, plain}) {
    ASSERT_EQ(reader.next(), Record::kRegion);
    const RegionRecord& r = reader.region();
    EXPECT_EQ(r.id, expected.id);
    ASSERT_EQ(r.measures.has_value(), expected.measures.has_value()) << "region " << r.id;
    if (!expected.measures) continue;
    const RegionMeasures& m = *r.measures;
    const RegionMeasures& e = *expected.measures;
    EXPECT_EQ(m.measure, e.measure);
    EXPECT_EQ(m.reason, e.reason);
    EXPECT_EQ(m.voxel_size, e.voxel_size);
    EXPECT_EQ(m.volume, e.volume);
    EXPECT_EQ(m.volume_error, e.volume_error);
    EXPECT_EQ(m.depth, e.depth);
    EXPECT_EQ(m.depth_error, e.depth_error);
    EXPECT_EQ(m.area, e.area);
    EXPECT_EQ(m.area_error, e.area_error);
    EXPECT_EQ(m.curve_length, e.curve_length);
    EXPECT_EQ(m.segments, e.segments);
  }
  EXPECT_EQ(reader.next(), Record::kTrailer);
}

TEST_F(RegionMeasuresTest, OnlyTheMeasuresFieldsAreWritten) {
  RegionRecord curve = region(0, 0, 0);
  curve.measures = RegionMeasures{};
  curve.measures->measure = "curve_length";
  curve.measures->curve_length = 2;
  const std::string file = path("curve.jsonl");
  write_report(file, {curve});
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find(R"("measures":{"measure":"curve_length","reason":"","voxel_size":0,)"
                            R"("curve_length":2,"segments":0})"),
            std::string::npos)
      << text.str();
  EXPECT_EQ(text.str().find("\"volume\""), std::string::npos);
}

TEST_F(RegionMeasuresTest, RejectsAnUnknownMeasureOrAMissingField) {
  RegionRecord r = region(0, 0, 1);
  r.measures = RegionMeasures{};
  r.measures->measure = "penetration";
  const std::string file = path("good.jsonl");
  write_report(file, {r});
  std::ifstream in(file);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string good = buffer.str();

  auto expect_error = [&](const std::string& from, const std::string& to, const std::string& problem) {
    std::string text = good;
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const std::string damaged = path("damaged.jsonl");
    std::ofstream(damaged) << text;
    try {
      ReportReader reader(damaged);
      while (reader.next() != Record::kEnd) {
      }
      ADD_FAILURE() << "no error for " << to;
    } catch (const snag::InputError& error) {
      const std::string what = error.what();
      EXPECT_EQ(error.where().line, 3u) << what;
      EXPECT_NE(what.find(problem), std::string::npos) << what;
    }
  };
  expect_error(R"("measure":"penetration")", R"("measure":"weight")", "unknown measure \"weight\"");
  expect_error(R"("depth":0,)", "", "depth");
}

}  // namespace
