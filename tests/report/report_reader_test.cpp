// ReportReader against hand-written JSON Lines reports: every record kind and
// field read back as written, every kind of damage rejected with the file, the
// line and the problem, and a synthetic report of about 200 MB read to time
// the reader (printed, not asserted).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "libcd/core/error.hpp"
#include "report/report_reader.hpp"

namespace {

using snag::report::ReportReader;
using Record = ReportReader::Record;
using snag::report::kNone;

class TempDir {
 public:
  TempDir() : path_(std::filesystem::temp_directory_path() / ("snag_report_reader_" + std::to_string(getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string file = (path_ / name).string();
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }
  std::string path(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// A complete report: two objects, two frames; in frame 12 an intersection, a
// VF and an EE collision (the EE one uncertain), an allowed intersection,
// three regions and a track that ended; then two open tracks and the trailer.
std::vector<std::string> fixture() {
  return {
      R"({"record":"header","format":"snag-report","version":2,"tool":"snag-scan","snag_version":"0.1.0",)"
      R"("source":"cloth.pc2 + body.pc2","objects":[)"
      R"({"name":"cloth","vertices":10,"file_vertices":12,"triangles":8,"edges":17,"weld":"exact","thickness":0.002},)"
      R"({"name":"body","vertices":6,"file_vertices":6,"triangles":8,"edges":12,"weld":"none","thickness":0.001}],)"
      R"("frame_count":2,"settings":{"mode":"all","backend":"cpu","precision":"certified","thickness":0.001,)"
      R"("lambda":1.2,"threads":4,"frames":"12:13","weld":"auto","events":"all","max_events":100000,)"
      R"("manifest":"scene.yaml"},"rules":{"pairs":[["cloth","body"]],"no_self":["body"],"neighbourhood":2,)"
      R"("thickness":[["cloth",0.002]],"allow":[{"objects":["cloth","*"],"kind":"intersection","frames":[10,20],)"
      R"("box":[[0,0,0],[1,1,1]],"note":"the collar"},{"objects":["*","*"],"kind":"any","frames":[5,null],)"
      R"("box":null,"note":""}],"fail":{"events":1,"collisions":0,"intersections":3,"regions":0,"tracks":2}},)"
      R"("certified":true})",
      R"({"record":"frame","position":0,"index":12,"time":0.5,"collisions":2,"vf":1,"ee":1,"uncertain":1,)"
      R"("intersections":1,"allowed":1,"regions":3})",
      R"({"record":"event","kind":"intersection","frame":12,"a":{"object":"cloth","face":3},)"
      R"("b":{"object":"body","face":7},"position":[0.25,-1.5,2],"region":0})",
      R"({"record":"event","kind":"collision","frame":12,"type":"vf","toi":12.25,"toi_interval":[12.25,12.2500001],)"
      R"("a":{"object":"cloth","vertex":11},"b":{"object":"body","face":2},"certainty":"proven",)"
      R"("position":[1,2,3],"region":1})",
      R"({"record":"event","kind":"collision","frame":12,"type":"ee","toi":12.5,"toi_interval":[12.5,12.5],)"
      R"("a":{"object":"cloth","edge":[3,4]},"b":{"object":"cloth","edge":[8,9]},"certainty":"uncertain",)"
      R"("position":[null,0,0],"region":2})",
      R"({"record":"event","kind":"intersection","frame":12,"a":{"object":"cloth","face":5},)"
      R"("b":{"object":"body","face":6},"position":[0.5,0.5,0.5],"region":null,"allowed":0})",
      R"({"record":"region","id":0,"kind":"intersection","objects":["cloth","body"],"frame":12,"track":0,)"
      R"("events":1,"face_count":2,"faces":[{"object":"cloth","ids":[3]},{"object":"body","ids":[7]}],)"
      R"("bounds":[[0,-2,1],[0.5,-1,3]],"centroid":[0.25,-1.5,2]})",
      R"({"record":"region","id":1,"kind":"collision","objects":["cloth","body"],"frame":12,"track":1,)"
      R"("events":1,"face_count":4,"faces":[{"object":"body","ids":[2]},{"object":"cloth","ids":[1,4,6]}],)"
      R"("bounds":[[1,2,3],[1,2,3]],"centroid":[1,2,3],"toi":12.25})",
      R"({"record":"region","id":2,"kind":"collision","objects":["cloth","cloth"],"frame":12,"track":2,)"
      R"("events":1,"face_count":2,"faces":[{"object":"cloth","ids":[0,2]}],)"
      R"("bounds":[[0,0,0],[0,0,0]],"centroid":[0,0,0],"toi":12.5})",
      R"({"record":"track","id":0,"kind":"intersection","objects":["cloth","body"],"first_frame":12,)"
      R"("last_frame":12,"frames":1,"regions":1,"events":1,"max_faces":2,"worst_frame":12,)"
      R"("bounds":[[0,-2,1],[0.5,-1,3]],"centroid":[0.25,-1.5,2],"merged_into":null})",
      R"({"record":"frame","position":1,"index":13,"time":0.541666,"collisions":0,"vf":0,"ee":0,"uncertain":0,)"
      R"("intersections":0,"allowed":0,"regions":0})",
      R"({"record":"track","id":1,"kind":"collision","objects":["cloth","body"],"first_frame":12,)"
      R"("last_frame":12,"frames":1,"regions":1,"events":1,"max_faces":4,"worst_frame":12,)"
      R"("bounds":[[1,2,3],[1,2,3]],"centroid":[1,2,3],"toi":12.25,"merged_into":null})",
      R"({"record":"track","id":2,"kind":"collision","objects":["cloth","cloth"],"first_frame":12,)"
      R"("last_frame":12,"frames":1,"regions":1,"events":1,"max_faces":2,"worst_frame":12,)"
      R"("bounds":[[0,0,0],[0,0,0]],"centroid":[0,0,0],"toi":12.5,"merged_into":1})",
      R"({"record":"trailer","frames":2,"summary":{"events":3,"collisions":2,"vf":1,"ee":1,"intersections":1,)"
      R"("uncertain":1,"allowed":1,"listed":4,"left_out":0,"not_checked":7,"neighbourhood":5,"regions":3,)"
      R"("tracks":3},"pairs":[{"kind":"intersection","objects":["cloth","body"],"events":1,"allowed":1,)"
      R"("regions":1,"tracks":1,"frames":1,"worst_frame":12,"worst_frame_events":1},)"
      R"({"kind":"collision","objects":["cloth","cloth"],"events":1,"allowed":0,"regions":1,"tracks":1,)"
      R"("frames":1,"worst_frame":null,"worst_frame_events":0}],"allow":[1,0],"largest_tracks":[)"
      R"({"id":1,"kind":"collision","objects":["cloth","body"],"first_frame":12,"last_frame":12,"frames":1,)"
      R"("regions":1,"events":1,"max_faces":4,"worst_frame":12,"bounds":[[1,2,3],[1,2,3]],"centroid":[1,2,3],)"
      R"("toi":12.25,"merged_into":null}],"verdict":{"pass":false,"failed":[{"what":"events","count":3,)"
      R"("threshold":1}]},"stages":{"grid": {"cells": 10, "seconds": 0.5}},"timing":{"total":1.5}})",
  };
}

std::string join(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

// The fixture with `from` replaced by `to` on line `line` (1-based).
std::string edited(std::size_t line, const std::string& from, const std::string& to) {
  std::vector<std::string> lines = fixture();
  std::string& text = lines.at(line - 1);
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return join(lines);
}

// Reads a whole report; returns the number of records after the header.
std::size_t read_all(const std::string& path) {
  ReportReader reader(path);
  std::size_t records = 0;
  while (reader.next() != Record::kEnd) ++records;
  return records;
}

class ReportReaderTest : public ::testing::Test {
 protected:
  // Reading `text` throws an InputError naming the file, `line` and `problem`.
  void expect_error(const std::string& text, std::size_t line, const std::string& problem) {
    const std::string path = dir_.write("damaged.jsonl", text);
    try {
      read_all(path);
      ADD_FAILURE() << "no error; expected line " << line << ": " << problem;
    } catch (const snag::InputError& error) {
      const std::string what = error.what();
      EXPECT_EQ(error.where().file, path) << what;
      EXPECT_EQ(error.where().line, line) << what;
      EXPECT_NE(what.find(problem), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
      EXPECT_EQ(what.rfind(path + ":" + std::to_string(line) + ": ", 0), 0u) << what;
    }
  }

  TempDir dir_;
};

TEST_F(ReportReaderTest, ReadsTheHeader) {
  ReportReader reader(dir_.write("report.jsonl", join(fixture())));
  const snag::report::Header& h = reader.header();
  EXPECT_EQ(reader.line(), 1u);
  EXPECT_EQ(h.version, 2);
  EXPECT_EQ(h.tool, "snag-scan");
  EXPECT_EQ(h.snag_version, "0.1.0");
  EXPECT_EQ(h.source, "cloth.pc2 + body.pc2");
  ASSERT_EQ(h.objects.size(), 2u);
  EXPECT_EQ(h.objects[0].name, "cloth");
  EXPECT_EQ(h.objects[0].vertices, 10u);
  EXPECT_EQ(h.objects[0].file_vertices, 12u);
  EXPECT_EQ(h.objects[0].triangles, 8u);
  EXPECT_EQ(h.objects[0].edges, 17u);
  EXPECT_EQ(h.objects[0].weld, "exact");
  EXPECT_EQ(h.objects[0].thickness, 0.002);
  EXPECT_EQ(h.objects[1].name, "body");
  EXPECT_EQ(h.objects[1].weld, "none");
  EXPECT_EQ(h.objects[1].thickness, 0.001);
  EXPECT_EQ(h.frame_count, 2u);
  const snag::report::ReportSettings& s = h.settings;
  EXPECT_EQ(s.mode, "all");
  EXPECT_EQ(s.backend, "cpu");
  EXPECT_EQ(s.precision, "certified");
  EXPECT_EQ(s.thickness, 0.001);
  EXPECT_EQ(s.lambda, 1.2);
  EXPECT_EQ(s.grid, "uniform") << "a report without the grid ran the uniform one";
  EXPECT_EQ(s.threads, 4u);
  EXPECT_EQ(s.frames, "12:13");
  EXPECT_EQ(s.weld, "auto");
  EXPECT_EQ(s.events, "all");
  EXPECT_EQ(s.max_events, 100000u);
  EXPECT_EQ(s.manifest, "scene.yaml");
  const snag::report::ScanRules& r = h.rules;
  ASSERT_EQ(r.pairs.size(), 1u);
  EXPECT_EQ(r.pairs[0], std::make_pair(std::string("cloth"), std::string("body")));
  EXPECT_EQ(r.no_self, std::vector<std::string>{"body"});
  EXPECT_EQ(r.neighbourhood, 2u);
  ASSERT_EQ(r.thickness.size(), 1u);
  EXPECT_EQ(r.thickness[0].first, "cloth");
  EXPECT_EQ(r.thickness[0].second, 0.002);
  ASSERT_EQ(r.allow.size(), 2u);
  EXPECT_EQ(r.allow[0].object_a, "cloth");
  EXPECT_EQ(r.allow[0].object_b, "") << "\"*\" is any object";
  ASSERT_TRUE(r.allow[0].kind.has_value());
  EXPECT_EQ(*r.allow[0].kind, snag::EventKind::kIntersection);
  EXPECT_EQ(r.allow[0].first_frame, 10u);
  EXPECT_EQ(r.allow[0].last_frame, 20u);
  ASSERT_TRUE(r.allow[0].box.has_value());
  EXPECT_EQ((*r.allow[0].box)[1], (snag::Vec3{1, 1, 1}));
  EXPECT_EQ(r.allow[0].note, "the collar");
  EXPECT_FALSE(r.allow[1].kind.has_value()) << "\"any\"";
  EXPECT_EQ(r.allow[1].first_frame, 5u);
  EXPECT_EQ(r.allow[1].last_frame, static_cast<std::size_t>(-1)) << "open-ended";
  EXPECT_FALSE(r.allow[1].box.has_value());
  EXPECT_EQ(r.fail.events, 1u);
  EXPECT_EQ(r.fail.collisions, 0u);
  EXPECT_EQ(r.fail.intersections, 3u);
  EXPECT_EQ(r.fail.tracks, 2u);
  EXPECT_TRUE(h.certified);
}

TEST_F(ReportReaderTest, ReadsEveryRecordInOrder) {
  ReportReader reader(dir_.write("report.jsonl", join(fixture())));
  ASSERT_EQ(reader.next(), Record::kFrame);
  EXPECT_EQ(reader.line(), 2u);
  const snag::report::FrameRecord& f = reader.frame();
  EXPECT_EQ(f.position, 0u);
  EXPECT_EQ(f.index, 12u);
  EXPECT_EQ(f.time, 0.5);
  EXPECT_EQ(f.collisions, 2u);
  EXPECT_EQ(f.vf, 1u);
  EXPECT_EQ(f.ee, 1u);
  EXPECT_EQ(f.uncertain, 1u);
  EXPECT_EQ(f.intersections, 1u);
  EXPECT_EQ(f.allowed, 1u);
  EXPECT_EQ(f.regions, 3u);

  ASSERT_EQ(reader.next(), Record::kEvent);
  {
    const snag::report::EventRecord& e = reader.event();
    EXPECT_EQ(e.kind, snag::EventKind::kIntersection);
    EXPECT_EQ(e.type, snag::ContactType::kTriangleTriangle);
    EXPECT_EQ(e.frame, 12u);
    EXPECT_EQ(e.a.object, 0u);
    EXPECT_EQ(e.a.id, 3u);
    EXPECT_EQ(e.b.object, 1u);
    EXPECT_EQ(e.b.id, 7u);
    EXPECT_EQ(e.position, (snag::Vec3{0.25, -1.5, 2}));
    EXPECT_EQ(e.region, 0u);
    EXPECT_EQ(e.allowed, kNone);
  }
  ASSERT_EQ(reader.next(), Record::kEvent);
  {
    const snag::report::EventRecord& e = reader.event();
    EXPECT_EQ(e.kind, snag::EventKind::kCollision);
    EXPECT_EQ(e.type, snag::ContactType::kVertexFace);
    EXPECT_EQ(e.toi, 12.25);
    EXPECT_EQ(e.toi_lo, 12.25);
    EXPECT_EQ(e.toi_hi, 12.2500001);
    EXPECT_EQ(e.a.object, 0u);
    EXPECT_EQ(e.a.id, 11u) << "a file vertex id beyond the welded vertex count";
    EXPECT_EQ(e.b.object, 1u);
    EXPECT_EQ(e.b.id, 2u);
    EXPECT_EQ(e.certainty, snag::Certainty::kProven);
    EXPECT_EQ(e.region, 1u);
  }
  ASSERT_EQ(reader.next(), Record::kEvent);
  {
    const snag::report::EventRecord& e = reader.event();
    EXPECT_EQ(e.type, snag::ContactType::kEdgeEdge);
    EXPECT_EQ(e.a.object, 0u);
    EXPECT_EQ(e.a.id, 3u);
    EXPECT_EQ(e.a.id2, 4u);
    EXPECT_EQ(e.b.object, 0u);
    EXPECT_EQ(e.b.id, 8u);
    EXPECT_EQ(e.b.id2, 9u);
    EXPECT_EQ(e.certainty, snag::Certainty::kUncertain);
    EXPECT_TRUE(std::isnan(e.position.x)) << "null reads back as NaN";
    EXPECT_EQ(e.region, 2u);
  }
  ASSERT_EQ(reader.next(), Record::kEvent);
  EXPECT_EQ(reader.event().region, kNone);
  EXPECT_EQ(reader.event().allowed, 0u);

  ASSERT_EQ(reader.next(), Record::kRegion);
  {
    const snag::report::RegionRecord& r = reader.region();
    EXPECT_EQ(r.id, 0u);
    EXPECT_EQ(r.kind, snag::EventKind::kIntersection);
    EXPECT_EQ(r.object_a, 0u);
    EXPECT_EQ(r.object_b, 1u);
    EXPECT_EQ(r.frame, 12u);
    EXPECT_EQ(r.track, 0u);
    EXPECT_EQ(r.events, 1u);
    EXPECT_EQ(r.faces_a, std::vector<std::size_t>{3});
    EXPECT_EQ(r.faces_b, std::vector<std::size_t>{7});
    EXPECT_EQ(r.bounds.lo, (snag::Vec3{0, -2, 1}));
    EXPECT_EQ(r.bounds.hi, (snag::Vec3{0.5, -1, 3}));
    EXPECT_EQ(r.centroid, (snag::Vec3{0.25, -1.5, 2}));
  }
  ASSERT_EQ(reader.next(), Record::kRegion);
  {
    const snag::report::RegionRecord& r = reader.region();
    EXPECT_EQ(r.kind, snag::EventKind::kCollision);
    EXPECT_EQ(r.faces_a, (std::vector<std::size_t>{1, 4, 6})) << "faces go by object, not by their order";
    EXPECT_EQ(r.faces_b, std::vector<std::size_t>{2});
    EXPECT_EQ(r.toi, 12.25);
  }
  ASSERT_EQ(reader.next(), Record::kRegion);
  {
    const snag::report::RegionRecord& r = reader.region();
    EXPECT_EQ(r.object_a, 0u);
    EXPECT_EQ(r.object_b, 0u);
    EXPECT_EQ(r.faces_a, (std::vector<std::size_t>{0, 2}));
    EXPECT_TRUE(r.faces_b.empty()) << "a self region has one list";
  }
  ASSERT_EQ(reader.next(), Record::kTrack);
  {
    const snag::report::TrackRecord& t = reader.track();
    EXPECT_EQ(t.id, 0u);
    EXPECT_EQ(t.kind, snag::EventKind::kIntersection);
    EXPECT_EQ(t.first_frame, 12u);
    EXPECT_EQ(t.last_frame, 12u);
    EXPECT_EQ(t.frames, 1u);
    EXPECT_EQ(t.regions, 1u);
    EXPECT_EQ(t.events, 1u);
    EXPECT_EQ(t.max_faces, 2u);
    EXPECT_EQ(t.worst_frame, 12u);
    EXPECT_EQ(t.bounds.hi, (snag::Vec3{0.5, -1, 3}));
    EXPECT_EQ(t.centroid, (snag::Vec3{0.25, -1.5, 2}));
    EXPECT_EQ(t.merged_into, kNone);
  }
  ASSERT_EQ(reader.next(), Record::kFrame);
  EXPECT_EQ(reader.frame().position, 1u);
  EXPECT_EQ(reader.frame().index, 13u);
  EXPECT_EQ(reader.frame().time, 0.541666);
  ASSERT_EQ(reader.next(), Record::kTrack);
  EXPECT_EQ(reader.track().toi, 12.25);
  ASSERT_EQ(reader.next(), Record::kTrack);
  EXPECT_EQ(reader.track().merged_into, 1u);
  EXPECT_EQ(reader.track().object_b, 0u);

  ASSERT_EQ(reader.next(), Record::kTrailer);
  EXPECT_EQ(reader.line(), 14u);
  const snag::report::Trailer& t = reader.trailer();
  EXPECT_EQ(t.frames, 2u);
  EXPECT_EQ(t.events, 3u);
  EXPECT_EQ(t.collisions, 2u);
  EXPECT_EQ(t.vf, 1u);
  EXPECT_EQ(t.ee, 1u);
  EXPECT_EQ(t.intersections, 1u);
  EXPECT_EQ(t.uncertain, 1u);
  EXPECT_EQ(t.allowed, 1u);
  EXPECT_EQ(t.listed, 4u);
  EXPECT_EQ(t.left_out, 0u);
  EXPECT_EQ(t.not_checked, 7u);
  EXPECT_EQ(t.neighbourhood, 5u);
  EXPECT_EQ(t.regions, 3u);
  EXPECT_EQ(t.tracks, 3u);
  ASSERT_EQ(t.pairs.size(), 2u);
  EXPECT_EQ(t.pairs[0].kind, snag::EventKind::kIntersection);
  EXPECT_EQ(t.pairs[0].object_b, 1u);
  EXPECT_EQ(t.pairs[0].events, 1u);
  EXPECT_EQ(t.pairs[0].allowed, 1u);
  EXPECT_EQ(t.pairs[0].regions, 1u);
  EXPECT_EQ(t.pairs[0].tracks, 1u);
  EXPECT_EQ(t.pairs[0].frames, 1u);
  EXPECT_EQ(t.pairs[0].worst_frame, 12u);
  EXPECT_EQ(t.pairs[0].worst_frame_events, 1u);
  EXPECT_EQ(t.pairs[1].worst_frame, kNone) << "null: no checked event";
  EXPECT_EQ(t.allow_counts, (std::vector<std::size_t>{1, 0}));
  ASSERT_EQ(t.largest_tracks.size(), 1u);
  EXPECT_EQ(t.largest_tracks[0].id, 1u);
  EXPECT_EQ(t.largest_tracks[0].max_faces, 4u);
  EXPECT_FALSE(t.pass);
  ASSERT_EQ(t.failed.size(), 1u);
  EXPECT_EQ(t.failed[0].what, "events");
  EXPECT_EQ(t.failed[0].count, 3u);
  EXPECT_EQ(t.failed[0].threshold, 1u);
  EXPECT_EQ(t.stages_json, R"({"grid":{"cells":10,"seconds":0.5}})");
  EXPECT_EQ(t.timing_json, R"({"total":1.5})");

  EXPECT_EQ(reader.next(), Record::kEnd);
  EXPECT_EQ(reader.next(), Record::kEnd);
}

TEST_F(ReportReaderTest, DoesNotDependOnKeyOrderOrLineEnds) {
  // Keys reversed in a frame record, CRLF line ends, no newline after the trailer.
  std::vector<std::string> lines = fixture();
  lines[10] = R"({"regions":0,"allowed":0,"intersections":0,"uncertain":0,"ee":0,"vf":0,"collisions":0,)"
              R"("time":0.541666,"index":13,"position":1,"record":"frame"})";
  std::string text;
  for (const std::string& line : lines) text += line + "\r\n";
  text.resize(text.size() - 2);
  EXPECT_EQ(read_all(dir_.write("crlf.jsonl", text)), 13u);
}

TEST_F(ReportReaderTest, ReadsALineLongerThanAChunk) {
  // A trailer of about 20 MB (the reader reads 8 MiB at a time).
  const std::string big(20u << 20, 'x');
  const std::string text = edited(14, R"("timing":{"total":1.5})", R"("timing":{"note":")" + big + R"("})");
  ReportReader reader(dir_.write("long.jsonl", text));
  Record record;
  while ((record = reader.next()) != Record::kTrailer) ASSERT_NE(record, Record::kEnd);
  EXPECT_EQ(reader.trailer().timing_json.size(), big.size() + 11);
  EXPECT_EQ(reader.next(), Record::kEnd);
}

TEST_F(ReportReaderTest, ReadsAReportWithNoFrames) {
  std::vector<std::string> lines = fixture();
  std::string header = lines[0];
  header.replace(header.find(R"("frame_count":2)"), 15, R"("frame_count":0)");
  const std::string trailer =
      R"({"record":"trailer","frames":0,"summary":{"events":0,"collisions":0,"vf":0,"ee":0,"intersections":0,)"
      R"("uncertain":0,"allowed":0,"listed":0,"left_out":0,"not_checked":0,"neighbourhood":0,"regions":0,)"
      R"("tracks":0},"pairs":[],"allow":[0,0],"largest_tracks":[],"verdict":{"pass":true,"failed":[]},)"
      R"("stages":{},"timing":{}})";
  EXPECT_EQ(read_all(dir_.write("empty_scan.jsonl", header + "\n" + trailer + "\n")), 1u);
}

TEST_F(ReportReaderTest, ReadsARegionWithoutFaceLists) {
  // Reports that list no events (--events none) list no faces either.
  ReportReader reader(dir_.write("no_faces.jsonl", edited(7, R"("faces":[{"object":"cloth","ids":[3]},{"object":"body","ids":[7]}],)", "")));
  Record record;
  while ((record = reader.next()) != Record::kRegion) ASSERT_NE(record, Record::kEnd);
  EXPECT_EQ(reader.region().events, 1u);
  EXPECT_TRUE(reader.region().faces_a.empty());
  EXPECT_TRUE(reader.region().faces_b.empty());
}

TEST_F(ReportReaderTest, RejectsAnEmptyFile) { expect_error("", 1, "empty"); }

TEST_F(ReportReaderTest, RejectsGarbage) {
  expect_error("PK\x03\x04 not a report at all\n", 1, "not a JSON record");
  expect_error("[1, 2, 3]\n", 1, "not a JSON object");
}

TEST_F(ReportReaderTest, RejectsAMissingFile) {
  try {
    ReportReader reader(dir_.path("no_such_report.jsonl"));
    ADD_FAILURE() << "no error";
  } catch (const snag::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("no_such_report.jsonl"), std::string::npos);
  }
}

TEST_F(ReportReaderTest, SaysToScanAgainForAVersion1Report) {
  // As version 1 was written: one indented document.
  expect_error("{\n \"version\": 1,\n \"tool\": \"snag-scan\",\n \"events\": []\n}\n", 1,
               "this is a version 1 report; scan the cache again with this snag-scan");
  // The same on one line.
  expect_error(R"({"version":1,"tool":"snag-scan","events":[]})"
               "\n",
               1, "version 1 report");
  expect_error(edited(1, R"("version":2)", R"("version":1)"), 1, "version 1 report");
}

TEST_F(ReportReaderTest, RejectsAnotherVersionOrFormat) {
  expect_error(edited(1, R"("version":2)", R"("version":3)"), 1, "version 3");
  expect_error(edited(1, R"("format":"snag-report")", R"("format":"other")"), 1, "not a snag report");
  std::vector<std::string> lines = fixture();
  std::swap(lines[0], lines[1]);
  expect_error(join(lines), 1, "not the header");
}

TEST_F(ReportReaderTest, RejectsAReportWithoutTrailer) {
  std::vector<std::string> lines = fixture();
  lines.pop_back();
  expect_error(join(lines), 14, "incomplete report (no trailer): the scan did not finish");
}

TEST_F(ReportReaderTest, RejectsATruncatedLine) {
  // Cut in the trailer (the last line) and in an event.
  std::string text = join(fixture());
  text.resize(text.size() - 40);
  expect_error(text, 14, "cut short");
  std::vector<std::string> lines = fixture();
  lines[3].resize(lines[3].size() / 2);
  expect_error(join(lines), 4, "not a JSON record");
}

TEST_F(ReportReaderTest, RejectsAnEmptyLine) {
  std::vector<std::string> lines = fixture();
  lines.insert(lines.begin() + 2, "");
  expect_error(join(lines), 3, "empty line");
}

TEST_F(ReportReaderTest, RejectsAKeyOfTheWrongType) {
  expect_error(edited(2, R"("index":12)", R"("index":"12")"), 2, R"(frame record: "index" is not a non-negative integer)");
  expect_error(edited(3, R"("face":3)", R"("face":-3)"), 3, R"("face" is not a non-negative integer)");
  expect_error(edited(3, R"("face":3)", R"("face":3.5)"), 3, R"("face" is not a non-negative integer)");
  expect_error(edited(4, R"("toi":12.25)", R"("toi":"soon")"), 4, R"("toi" is not a number)");
  expect_error(edited(4, R"("position":[1,2,3])", R"("position":[1,2])"), 4, R"("position" is not [x, y, z])");
  expect_error(edited(1, R"("certified":true)", R"("certified":1)"), 1, R"("certified" is not true or false)");
  expect_error(edited(5, R"("certainty":"uncertain")", R"("certainty":"maybe")"), 5, "unknown certainty");
  expect_error(edited(3, R"("kind":"intersection")", R"("kind":"graze")"), 3, "unknown kind");
  expect_error(edited(4, R"("type":"vf")", R"("type":"tt")"), 4, "unknown collision type");
  expect_error(edited(1, R"("mode":"all")", R"("mode":"both")"), 1, "unknown mode");
  expect_error(edited(1, R"("lambda":1.2,)", R"("lambda":1.2,"grid":"octree",)"), 1, "unknown grid");
}

TEST_F(ReportReaderTest, ReadsTheGrid) {
  const std::string path = dir_.write("adaptive.jsonl", edited(1, R"("lambda":1.2,)", R"("lambda":1.2,"grid":"adaptive",)"));
  ReportReader reader(path);
  EXPECT_EQ(reader.header().settings.grid, "adaptive");
}

TEST_F(ReportReaderTest, RejectsAMissingKey) {
  expect_error(edited(4, R"("toi":12.25,)", ""), 4, R"(event record: "toi" is missing)");
  expect_error(edited(1, R"("frame_count":2,)", ""), 1, R"(header record: "frame_count" is missing)");
  expect_error(edited(2, R"("record":"frame",)", ""), 2, R"(no "record" key)");
}

TEST_F(ReportReaderTest, RejectsAnUnknownObject) {
  expect_error(edited(3, R"("object":"body")", R"("object":"ghost")"), 3, "\"ghost\", which the header does not list");
  expect_error(edited(7, R"("objects":["cloth","body"])", R"("objects":["cloth","ghost"])"), 7, "ghost");
}

TEST_F(ReportReaderTest, RejectsAnIdOutOfRange) {
  expect_error(edited(3, R"("face":7)", R"("face":8)"), 3, "face 8 of \"body\" is out of range (it has 8)");
  expect_error(edited(4, R"("vertex":11)", R"("vertex":12)"), 4, "vertex 12 of \"cloth\" is out of range (it has 12)");
  expect_error(edited(5, R"("edge":[3,4])", R"("edge":[3,40])"), 5, "edge vertex 40");
  expect_error(edited(7, R"("ids":[7])", R"("ids":[9])"), 7, "out of range");
  expect_error(edited(6, R"("allowed":0)", R"("allowed":2)"), 6, "allow rule 2 is out of range");
}

TEST_F(ReportReaderTest, RejectsRecordsOutOfOrder) {
  expect_error(edited(11, R"("position":1)", R"("position":2)"), 11, "position 2 where 1 comes next");
  expect_error(edited(11, R"("index":13)", R"("index":12)"), 11, "does not come after frame 12");
  expect_error(edited(3, R"("frame":12)", R"("frame":13)"), 3, "frame 13 under the record of frame 12");
  std::vector<std::string> lines = fixture();
  std::swap(lines[5], lines[6]);  // an event after a region
  expect_error(join(lines), 7, "event record after the frame's regions");
  lines = fixture();
  lines.insert(lines.begin() + 1, lines[2]);  // an event before any frame
  expect_error(join(lines), 2, "before the first frame");
  lines = fixture();
  lines.push_back(lines[1]);
  expect_error(join(lines), 15, "a \"frame\" record after the trailer");
  lines = fixture();
  lines.insert(lines.begin() + 3, lines[0]);
  expect_error(join(lines), 4, "a second header");
  lines = fixture();
  lines[3] = R"({"record":"comment","text":"hello"})";
  expect_error(join(lines), 4, "unknown record \"comment\"");
}

TEST_F(ReportReaderTest, RejectsAnEventNamingARegionItsFrameLacks) {
  expect_error(edited(3, R"("region":0)", R"("region":9)"), 3, "region 9 is not a region of frame 12");
}

TEST_F(ReportReaderTest, RejectsARegionThatContradictsItself) {
  expect_error(edited(7, R"("face_count":2)", R"("face_count":3)"), 7, "\"face_count\" is 3 but it lists 2 faces");
  expect_error(edited(8, R"("ids":[1,4,6])", R"("ids":[1,6,4])"), 8, "not increasing");
  expect_error(edited(7, R"("objects":["cloth","body"])", R"("objects":["body","cloth"])"), 7,
               "not in the header's order");
  expect_error(edited(9, R"("faces":[{"object":"cloth","ids":[0,2]}])",
                      R"("faces":[{"object":"cloth","ids":[0]},{"object":"cloth","ids":[2]}])"),
               9, "not one for each of its 1 objects");
}

TEST_F(ReportReaderTest, RejectsATrackOutsideTheFramesRead) {
  expect_error(edited(10, R"("last_frame":12)", R"("last_frame":13)"), 10, "not a frame of the report");
}

TEST_F(ReportReaderTest, RejectsALineLongerThanTheLimit) {
  // 257 MiB without a line end (a sparse file: quick to make and to read).
  const std::string path = dir_.path("huge.jsonl");
  std::ofstream(path) << "{";
  std::filesystem::resize_file(path, std::uintmax_t{257} << 20);
  try {
    ReportReader reader(path);
    ADD_FAILURE() << "no error";
  } catch (const snag::InputError& error) {
    EXPECT_EQ(error.where().line, 1u);
    EXPECT_NE(std::string(error.what()).find("longer than 256 MiB"), std::string::npos) << error.what();
  }
}

// About 200 MB: 800 frames of 1000 events each (intersections and VF and EE
// collisions in turn), one region per frame naming them all, and a track.
TEST_F(ReportReaderTest, ReadsALargeReportQuickly) {
  const std::size_t frames = 800, per_frame = 1000;
  const std::string path = dir_.path("large.jsonl");
  std::size_t bytes = 0;
  {
    std::vector<std::string> lines = fixture();
    std::string header = lines[0];
    header.replace(header.find(R"("frame_count":2)"), 15, R"("frame_count":)" + std::to_string(frames));
    std::FILE* out = std::fopen(path.c_str(), "wb");
    ASSERT_NE(out, nullptr);
    std::string text = header + "\n";
    char line[512];
    for (std::size_t f = 0; f < frames; ++f) {
      const std::size_t index = 100 + f;
      std::snprintf(line, sizeof line,
                    R"({"record":"frame","position":%zu,"index":%zu,"time":%.17g,"collisions":%zu,"vf":%zu,)"
                    R"("ee":%zu,"uncertain":0,"intersections":%zu,"allowed":0,"regions":1})"
                    "\n",
                    f, index, index / 24.0, 2 * per_frame / 3, per_frame / 3, per_frame / 3, per_frame / 3);
      text += line;
      for (std::size_t k = 0; k < per_frame; ++k) {
        const double x = 0.001 * static_cast<double>(k) + 0.1234567890123, y = -0.75 + 1e-7 * static_cast<double>(f);
        switch (k % 3) {
          case 0:
            std::snprintf(line, sizeof line,
                          R"({"record":"event","kind":"intersection","frame":%zu,"a":{"object":"cloth","face":%zu},)"
                          R"("b":{"object":"body","face":%zu},"position":[%.17g,%.17g,%.17g],"region":0})"
                          "\n",
                          index, k % 8, (k / 8) % 8, x, y, x * y);
            break;
          case 1:
            std::snprintf(line, sizeof line,
                          R"({"record":"event","kind":"collision","frame":%zu,"type":"vf","toi":%.17g,)"
                          R"("toi_interval":[%.17g,%.17g],"a":{"object":"cloth","vertex":%zu},)"
                          R"("b":{"object":"body","face":%zu},"certainty":"proven","position":[%.17g,%.17g,%.17g],)"
                          R"("region":0})"
                          "\n",
                          index, index + x / 2, index + x / 2, index + x / 2 + 1e-9, k % 12, k % 8, x, y, x + y);
            break;
          default:
            std::snprintf(line, sizeof line,
                          R"({"record":"event","kind":"collision","frame":%zu,"type":"ee","toi":%.17g,)"
                          R"("toi_interval":[%.17g,%.17g],"a":{"object":"cloth","edge":[%zu,%zu]},)"
                          R"("b":{"object":"body","edge":[%zu,%zu]},"certainty":"proven",)"
                          R"("position":[%.17g,%.17g,%.17g],"region":0})"
                          "\n",
                          index, index + x / 3, index + x / 3, index + x / 3, k % 11, k % 11 + 1, k % 5, k % 5 + 1,
                          x, y, y - x);
            break;
        }
        text += line;
      }
      std::snprintf(line, sizeof line,
                    R"({"record":"region","id":0,"kind":"intersection","objects":["cloth","body"],"frame":%zu,)"
                    R"("track":0,"events":%zu,"face_count":3,"faces":[{"object":"cloth","ids":[0,1]},)"
                    R"({"object":"body","ids":[5]}],"bounds":[[0,0,0],[1,1,1]],"centroid":[0.5,0.5,0.5]})"
                    "\n",
                    index, per_frame);
      text += line;
      if (text.size() > (4u << 20)) {
        bytes += std::fwrite(text.data(), 1, text.size(), out);
        text.clear();
      }
    }
    std::snprintf(line, sizeof line,
                  R"({"record":"track","id":0,"kind":"intersection","objects":["cloth","body"],"first_frame":100,)"
                  R"("last_frame":%zu,"frames":%zu,"regions":%zu,"events":%zu,"max_faces":3,"worst_frame":100,)"
                  R"("bounds":[[0,0,0],[1,1,1]],"centroid":[0.5,0.5,0.5],"merged_into":null})"
                  "\n",
                  100 + frames - 1, frames, frames, frames * per_frame / 3);
    text += line;
    std::snprintf(line, sizeof line,
                  R"({"record":"trailer","frames":%zu,"summary":{"events":%zu,"collisions":0,"vf":0,"ee":0,)"
                  R"("intersections":0,"uncertain":0,"allowed":0,"listed":0,"left_out":0,"not_checked":0,)"
                  R"("neighbourhood":0,"regions":0,"tracks":1},"pairs":[],"allow":[0,0],"largest_tracks":[],)"
                  R"("verdict":{"pass":false,"failed":[]},"stages":{},"timing":{}})"
                  "\n",
                  frames, frames * per_frame);
    text += line;
    bytes += std::fwrite(text.data(), 1, text.size(), out);
    ASSERT_EQ(std::fclose(out), 0);
  }

  const auto start = std::chrono::steady_clock::now();
  ReportReader reader(path);
  std::size_t frame_records = 0, events = 0, vf = 0, ee = 0, regions = 0, tracks = 0, trailers = 0;
  std::size_t face_sum = 0;
  double x_sum = 0;
  for (Record record; (record = reader.next()) != Record::kEnd;) {
    switch (record) {
      case Record::kFrame: ++frame_records; break;
      case Record::kEvent: {
        const snag::report::EventRecord& e = reader.event();
        ++events;
        vf += e.type == snag::ContactType::kVertexFace;
        ee += e.type == snag::ContactType::kEdgeEdge;
        face_sum += e.b.id;
        x_sum += e.position.x;
        break;
      }
      case Record::kRegion: ++regions; break;
      case Record::kTrack: ++tracks; break;
      case Record::kTrailer: ++trailers; break;
      case Record::kEnd: break;
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("ReportReader: %.1f MB (%zu records) in %.3f s: %.0f MB/s\n", 1e-6 * static_cast<double>(bytes),
              reader.line(), seconds, 1e-6 * static_cast<double>(bytes) / seconds);

  EXPECT_EQ(frame_records, frames);
  EXPECT_EQ(events, frames * per_frame);
  EXPECT_EQ(vf, frames * (per_frame / 3));
  EXPECT_EQ(ee, frames * (per_frame / 3));
  EXPECT_EQ(regions, frames);
  EXPECT_EQ(tracks, 1u);
  EXPECT_EQ(trailers, 1u);
  std::size_t expected_faces = 0;
  double expected_x = 0;
  for (std::size_t k = 0; k < per_frame; ++k) {
    expected_faces += k % 3 == 0 ? (k / 8) % 8 : k % 3 == 1 ? k % 8 : k % 5;
    expected_x += 0.001 * static_cast<double>(k) + 0.1234567890123;
  }
  EXPECT_EQ(face_sum, frames * expected_faces);
  EXPECT_NEAR(x_sum, static_cast<double>(frames) * expected_x, 1e-6);
  EXPECT_GT(bytes, 150u << 20);
}

}  // namespace
