#include "report/report_writer.hpp"

#include <algorithm>
#include <stdexcept>
#include <string_view>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace snag::report {

namespace {

constexpr std::size_t kFlushBytes = 1 << 20;

const char* certainty_name(Certainty c) { return c == Certainty::kProven ? "proven" : "uncertain"; }

}  // namespace

const char* kind_name(EventKind kind) { return kind == EventKind::kCollision ? "collision" : "intersection"; }

const char* type_name(ContactType type) {
  switch (type) {
    case ContactType::kVertexFace: return "vf";
    case ContactType::kEdgeEdge: return "ee";
    case ContactType::kTriangleTriangle: return "tt";
  }
  return "?";
}

ReportWriter::ReportWriter(std::ostream& out) : out_(out) {}

void ReportWriter::end_line() {
  line_.raw("}\n");
  if (line_.text().size() >= kFlushBytes) flush();
}

void ReportWriter::flush() {
  out_.write(line_.text().data(), static_cast<std::streamsize>(line_.text().size()));
  line_.clear();
  out_.flush();
  if (!out_) throw std::runtime_error("writing the report failed");
}

void ReportWriter::object_name(std::size_t o) {
  line_.string(o < names_.size() ? std::string_view(names_[o]) : std::string_view("?"));
}

void ReportWriter::object_pair(std::size_t a, std::size_t b) {
  line_.key("objects").raw("[");
  object_name(a);
  line_.raw(",");
  object_name(b);
  line_.raw("]");
}

void ReportWriter::use_names_of(const Header& h) {
  region_faces_ = h.settings.events != "none";
  names_.clear();
  for (const ObjectInfo& o : h.objects) names_.push_back(o.name);
}

void ReportWriter::write_header(const Header& h) {
  use_names_of(h);
  JsonText& j = line_;
  j.raw("{").key("record", true).string("header");
  j.key("format").string("snag-report");
  j.key("version").number(h.version);
  j.key("tool").string(h.tool);
  j.key("snag_version").string(h.snag_version);
  j.key("source").string(h.source);
  j.key("objects").raw("[");
  for (std::size_t i = 0; i < h.objects.size(); ++i) {
    const ObjectInfo& o = h.objects[i];
    if (i) j.raw(",");
    j.raw("{").key("name", true).string(o.name);
    j.key("vertices").number(o.vertices);
    j.key("file_vertices").number(o.file_vertices);
    j.key("triangles").number(o.triangles);
    j.key("edges").number(o.edges);
    j.key("weld").string(o.weld);
    j.key("thickness").number(o.thickness);
    j.raw("}");
  }
  j.raw("]");
  j.key("frame_count").number(h.frame_count);
  const ReportSettings& s = h.settings;
  j.key("settings").raw("{").key("mode", true).string(s.mode);
  j.key("backend").string(s.backend);
  j.key("precision").string(s.precision);
  j.key("thickness").number(s.thickness);
  j.key("lambda").number(s.lambda);
  j.key("grid").string(s.grid);
  j.key("threads").number(s.threads);
  j.key("frames").string(s.frames);
  j.key("weld").string(s.weld);
  j.key("events").string(s.events);
  j.key("max_events").number(s.max_events);
  j.key("manifest").string(s.manifest);
  j.raw("}");
  const ScanRules& r = h.rules;
  j.key("rules").raw("{").key("pairs", true).raw("[");
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    j.raw(i ? ",[" : "[").string(r.pairs[i].first).raw(",").string(r.pairs[i].second).raw("]");
  }
  j.raw("]").key("no_self").raw("[");
  for (std::size_t i = 0; i < r.no_self.size(); ++i) {
    if (i) j.raw(",");
    j.string(r.no_self[i]);
  }
  j.raw("]").key("neighbourhood").number(r.neighbourhood);
  j.key("thickness").raw("[");
  for (std::size_t i = 0; i < r.thickness.size(); ++i) {
    j.raw(i ? ",[" : "[").string(r.thickness[i].first).raw(",").number(r.thickness[i].second).raw("]");
  }
  j.raw("]").key("allow").raw("[");
  for (std::size_t i = 0; i < r.allow.size(); ++i) {
    const AllowRule& a = r.allow[i];
    if (i) j.raw(",");
    j.raw("{").key("objects", true).raw("[");
    j.string(a.object_a.empty() ? "*" : a.object_a).raw(",").string(a.object_b.empty() ? "*" : a.object_b).raw("]");
    j.key("kind").string(a.kind ? kind_name(*a.kind) : "any");
    j.key("frames").raw("[").number(a.first_frame).raw(",").optional(a.last_frame, kNone).raw("]");
    j.key("box");
    if (a.box) {
      j.raw("[").vec3((*a.box)[0]).raw(",").vec3((*a.box)[1]).raw("]");
    } else {
      j.null();
    }
    j.key("note").string(a.note);
    j.raw("}");
  }
  const FailThresholds& f = r.fail;
  j.raw("]").key("fail").raw("{").key("events", true).number(f.events);
  j.key("collisions").number(f.collisions);
  j.key("intersections").number(f.intersections);
  j.key("regions").number(f.regions);
  j.key("tracks").number(f.tracks);
  j.raw("}}");
  j.key("certified").boolean(h.certified);
  end_line();
}

void ReportWriter::write_frame(const FrameRecord& f) {
  JsonText& j = line_;
  j.raw("{").key("record", true).string("frame");
  j.key("position").number(f.position);
  j.key("index").number(f.index);
  j.key("time").number(f.time);
  j.key("collisions").number(f.collisions);
  j.key("vf").number(f.vf);
  j.key("ee").number(f.ee);
  j.key("uncertain").number(f.uncertain);
  j.key("intersections").number(f.intersections);
  j.key("allowed").number(f.allowed);
  j.key("regions").number(f.regions);
  end_line();
}

namespace {

// One event line; `names` are the header's object names. A free function so
// that blocks of events can be formatted on several threads at once.
void format_event(JsonText& j, const EventRecord& e, const std::vector<std::string>& names) {
  // A view, not a std::string: the name is not copied for every event.
  auto name = [&](std::size_t o) { j.string(o < names.size() ? std::string_view(names[o]) : std::string_view("?")); };
  j.raw("{").key("record", true).string("event");
  j.key("kind").string(kind_name(e.kind));
  j.key("frame").number(e.frame);
  auto ref = [&](const ElementRef& r, const char* what) {
    j.raw("{").key("object", true);
    name(r.object);
    j.key(what);
    if (what[0] == 'e') {
      j.raw("[").number(r.id).raw(",").number(r.id2).raw("]");
    } else {
      j.number(r.id);
    }
    j.raw("}");
  };
  if (e.kind == EventKind::kCollision) {
    j.key("type").string(type_name(e.type));
    j.key("toi").number(e.toi);
    j.key("toi_interval").raw("[").number(e.toi_lo).raw(",").number(e.toi_hi).raw("]");
    const bool vf = e.type == ContactType::kVertexFace;
    j.key("a");
    ref(e.a, vf ? "vertex" : "edge");
    j.key("b");
    ref(e.b, vf ? "face" : "edge");
    j.key("certainty").string(certainty_name(e.certainty));
  } else {
    j.key("a");
    ref(e.a, "face");
    j.key("b");
    ref(e.b, "face");
  }
  j.key("position").vec3(e.position);
  j.key("region").optional(e.region, kNone);
  if (e.allowed != kNone) j.key("allowed").number(e.allowed);
  j.raw("}\n");
}

}  // namespace

void ReportWriter::write_event(const EventRecord& e) {
  format_event(line_, e, names_);
  if (line_.text().size() >= kFlushBytes) flush();
}

void ReportWriter::write_events(std::size_t count, const std::function<EventRecord(std::size_t)>& event) {
  constexpr std::size_t kBlock = 2048;
  if (count < 2 * kBlock) {
    for (std::size_t i = 0; i < count; ++i) write_event(event(i));
    return;
  }
  // Blocks are formatted a batch at a time into buffers kept from batch to
  // batch and frame to frame: the text of a batch, not of the whole frame,
  // is held at once, and the buffers' pages are touched once per run
  // instead of fresh pages (page faults) for every frame's text.
  constexpr std::size_t kBlocksPerBatch = 16;
  flush();
  if (blocks_.size() < kBlocksPerBatch) blocks_.resize(kBlocksPerBatch);
  for (std::size_t first = 0; first < count; first += kBlock * kBlocksPerBatch) {
    const std::size_t end = std::min(count, first + kBlock * kBlocksPerBatch);
    const std::size_t blocks = (end - first + kBlock - 1) / kBlock;
    // Isolated: while it waits for its blocks, this thread (the scan's sink)
    // must not take up the scan's own tasks, which would hold the report back
    // for as long as one of them runs.
    tbb::this_task_arena::isolate([&] {
      tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        JsonText& block = blocks_[b];
        block.clear();
        const std::size_t block_first = first + b * kBlock;
        for (std::size_t i = block_first; i < std::min(end, block_first + kBlock); ++i)
          format_event(block, event(i), names_);
      });
    });
    for (std::size_t b = 0; b < blocks; ++b) {
      out_.write(blocks_[b].text().data(), static_cast<std::streamsize>(blocks_[b].text().size()));
    }
    if (!out_) throw std::runtime_error("writing the report failed");
  }
}

void ReportWriter::write_region(const RegionRecord& r) {
  JsonText& j = line_;
  j.raw("{").key("record", true).string("region");
  j.key("id").number(r.id);
  j.key("kind").string(kind_name(r.kind));
  object_pair(r.object_a, r.object_b);
  j.key("frame").number(r.frame);
  j.key("track").number(r.track);
  j.key("events").number(r.events);
  j.key("face_count").number(r.face_count);
  auto faces = [&](std::size_t object, const std::vector<std::size_t>& ids) {
    j.raw("{").key("object", true);
    object_name(object);
    j.key("ids").raw("[");
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (i) j.raw(",");
      j.number(ids[i]);
    }
    j.raw("]}");
  };
  if (region_faces_) {
    j.key("faces").raw("[");
    faces(r.object_a, r.faces_a);
    if (r.object_b != r.object_a) {
      j.raw(",");
      faces(r.object_b, r.faces_b);
    }
    j.raw("]");
  }
  j.key("bounds").raw("[").vec3(r.bounds.lo).raw(",").vec3(r.bounds.hi).raw("]");
  j.key("centroid").vec3(r.centroid);
  if (r.kind == EventKind::kCollision) j.key("toi").number(r.toi);
  if (r.measures) region_measures(*r.measures);
  end_line();
}

void ReportWriter::region_measures(const RegionMeasures& m) {
  JsonText& j = line_;
  j.key("measures").raw("{").key("measure", true).string(m.measure);
  j.key("reason").string(m.reason);
  j.key("voxel_size").number(m.voxel_size);
  if (m.measure == "overlap_volume" || m.measure == "self_overlap_volume") {
    j.key("volume").number(m.volume);
    j.key("volume_error").number(m.volume_error);
  } else if (m.measure == "penetration") {
    j.key("depth").number(m.depth);
    j.key("depth_error").number(m.depth_error);
    j.key("area").number(m.area);
    j.key("area_error").number(m.area_error);
  } else if (m.measure == "curve_length") {
    j.key("curve_length").number(m.curve_length);
    j.key("segments").number(m.segments);
  }
  j.raw("}");
}

void ReportWriter::track_fields(const TrackRecord& t) {
  JsonText& j = line_;
  j.key("id", true).number(t.id);
  j.key("kind").string(kind_name(t.kind));
  object_pair(t.object_a, t.object_b);
  j.key("first_frame").number(t.first_frame);
  j.key("last_frame").number(t.last_frame);
  j.key("frames").number(t.frames);
  j.key("regions").number(t.regions);
  j.key("events").number(t.events);
  j.key("max_faces").number(t.max_faces);
  j.key("worst_frame").number(t.worst_frame);
  j.key("bounds").raw("[").vec3(t.bounds.lo).raw(",").vec3(t.bounds.hi).raw("]");
  j.key("centroid").vec3(t.centroid);
  if (t.kind == EventKind::kCollision) j.key("toi").number(t.toi);
  j.key("merged_into").optional(t.merged_into, kNone);
}

void ReportWriter::write_track(const TrackRecord& t) {
  line_.raw("{").key("record", true).string("track").raw(",");
  track_fields(t);
  end_line();
}

void ReportWriter::write_trailer(const Trailer& t) {
  JsonText& j = line_;
  j.raw("{").key("record", true).string("trailer");
  j.key("frames").number(t.frames);
  j.key("summary").raw("{").key("events", true).number(t.events);
  j.key("collisions").number(t.collisions);
  j.key("vf").number(t.vf);
  j.key("ee").number(t.ee);
  j.key("intersections").number(t.intersections);
  j.key("uncertain").number(t.uncertain);
  j.key("allowed").number(t.allowed);
  j.key("listed").number(t.listed);
  j.key("left_out").number(t.left_out);
  j.key("not_checked").number(t.not_checked);
  j.key("neighbourhood").number(t.neighbourhood);
  j.key("regions").number(t.regions);
  j.key("tracks").number(t.tracks);
  j.raw("}");
  j.key("pairs").raw("[");
  for (std::size_t i = 0; i < t.pairs.size(); ++i) {
    const PairSummary& p = t.pairs[i];
    if (i) j.raw(",");
    j.raw("{").key("kind", true).string(kind_name(p.kind));
    object_pair(p.object_a, p.object_b);
    j.key("events").number(p.events);
    j.key("allowed").number(p.allowed);
    j.key("regions").number(p.regions);
    j.key("tracks").number(p.tracks);
    j.key("frames").number(p.frames);
    j.key("worst_frame");
    if (p.events > 0) {
      j.number(p.worst_frame);
    } else {
      j.null();
    }
    j.key("worst_frame_events").number(p.worst_frame_events);
    j.raw("}");
  }
  j.raw("]").key("allow").raw("[");
  for (std::size_t i = 0; i < t.allow_counts.size(); ++i) {
    if (i) j.raw(",");
    j.number(t.allow_counts[i]);
  }
  j.raw("]").key("largest_tracks").raw("[");
  for (std::size_t i = 0; i < t.largest_tracks.size(); ++i) {
    j.raw(i ? ",{" : "{");
    track_fields(t.largest_tracks[i]);
    j.raw("}");
  }
  j.raw("]");
  j.key("verdict").raw("{").key("pass", true).boolean(t.pass).key("failed").raw("[");
  for (std::size_t i = 0; i < t.failed.size(); ++i) {
    if (i) j.raw(",");
    j.raw("{").key("what", true).string(t.failed[i].what);
    j.key("count").number(t.failed[i].count);
    j.key("threshold").number(t.failed[i].threshold);
    j.raw("}");
  }
  j.raw("]}");
  j.key("stages").raw(t.stages_json);
  j.key("timing").raw(t.timing_json);
  end_line();
  flush();
}

}  // namespace snag::report
