#include "report/report_sink.hpp"

#include <algorithm>

namespace snag::report {

namespace {

constexpr std::size_t kLargestTracks = 5;

}  // namespace

ReportSink::ReportSink(const Scene& scene, const Header& header, const RuleSet& rules, ReportWriter* writer,
                       Redecide redecide)
    : scene_(scene),
      header_(header),
      rules_(rules),
      writer_(writer),
      redecide_(std::move(redecide)),
      regions_(scene),
      tracks_(scene) {
  trailer_.allow_counts.assign(rules_.rules().allow.size(), 0);
  if (writer_) writer_->write_header(header_);
}

PairSummary& ReportSink::pair(EventKind kind, std::size_t a, std::size_t b) {
  auto [it, inserted] = pairs_.try_emplace(PairKey{static_cast<int>(kind), a, b});
  if (inserted) {
    it->second.kind = kind;
    it->second.object_a = a;
    it->second.object_b = b;
  }
  return it->second;
}

EventRecord ReportSink::event_record(const Event& e) const {
  auto vertex = [&](Index v) {
    const std::size_t o = scene_.object_of_vertex(v);
    return ElementRef{o, file_vertex_id(scene_.objects()[o], v - scene_.vertex_offset(o)), 0};
  };
  auto face = [&](Index f) {
    const std::size_t o = scene_.object_of_triangle(f);
    return ElementRef{o, f - scene_.triangle_offset(o), 0};
  };
  auto edge = [&](Index id) {
    const std::size_t o = scene_.object_of_edge(id);
    const Object& object = scene_.objects()[o];
    const Edge& ends = scene_.edges()[id];
    const Index base = scene_.vertex_offset(o);
    return ElementRef{o, file_vertex_id(object, ends[0] - base), file_vertex_id(object, ends[1] - base)};
  };
  EventRecord r;
  r.kind = e.kind;
  r.type = e.type;
  r.frame = e.frame;
  r.position = e.position;
  r.certainty = e.certainty;
  if (e.kind == EventKind::kIntersection) {
    r.a = face(e.a);
    r.b = face(e.b);
  } else {
    r.toi = static_cast<double>(e.frame) + e.toi_lo;
    r.toi_lo = r.toi;
    r.toi_hi = static_cast<double>(e.frame) + e.toi_hi;
    if (e.type == ContactType::kVertexFace) {
      r.a = vertex(e.a);
      r.b = face(e.b);
    } else {
      r.a = edge(e.a);
      r.b = edge(e.b);
    }
  }
  return r;
}

void ReportSink::frame(ScannedFrame& frame) {
  std::vector<Event>& events = *frame.events;
  if (redecide_ && frame.x_next) redecide_(*frame.x, *frame.x_next, events);

  FrameRecord record;
  record.position = frame.position;
  record.index = frame.summary.frame;
  record.time = frame.time;
  in_region_.clear();
  allowed_by_.clear();
  in_region_.reserve(events.size());
  allowed_by_.reserve(events.size());
  // Per pair and kind, this frame's checked events: for frames affected and the worst frame.
  std::map<PairKey, std::size_t> checked_here;
  // The events of a pair come in long runs: the last pair's summary and
  // count are kept at hand instead of two map look-ups per event.
  PairKey last_key{-1, 0, 0};
  PairSummary* last_summary = nullptr;
  std::size_t* last_checked = nullptr;
  // The kept events are moved down in place (the scan lets the sink remove
  // events): nothing is copied while no rule drops any.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    const Disposition d = rules_.classify(e);
    if (d.kind == Disposition::kNotChecked) {
      ++trailer_.not_checked;
      continue;
    }
    if (d.kind == Disposition::kNeighbourhood) {
      ++trailer_.neighbourhood;
      continue;
    }
    const auto [a, b] = event_objects(scene_, e);
    const PairKey key{static_cast<int>(e.kind), a, b};
    if (key != last_key) {
      last_key = key;
      last_summary = &pair(e.kind, a, b);
      last_checked = nullptr;
    }
    PairSummary& summary = *last_summary;
    if (kept != i) events[kept] = e;
    ++kept;
    if (d.kind == Disposition::kAllowed) {
      in_region_.push_back(0);
      allowed_by_.push_back(d.rule);
      ++record.allowed;
      ++summary.allowed;
      ++trailer_.allowed;
      ++trailer_.allow_counts[d.rule];
      continue;
    }
    in_region_.push_back(1);
    allowed_by_.push_back(kNone);
    ++summary.events;
    if (!last_checked) last_checked = &checked_here[key];
    ++*last_checked;
    if (e.kind == EventKind::kCollision) {
      ++record.collisions;
      record.vf += e.type == ContactType::kVertexFace;
      record.ee += e.type == ContactType::kEdgeEdge;
      record.uncertain += e.certainty == Certainty::kUncertain;
    } else {
      ++record.intersections;
    }
  }
  events.resize(kept);
  for (const auto& [key, count] : checked_here) {
    PairSummary& summary = pair(static_cast<EventKind>(std::get<0>(key)), std::get<1>(key), std::get<2>(key));
    ++summary.frames;
    if (count > summary.worst_frame_events) {
      summary.worst_frame_events = count;
      summary.worst_frame = record.index;
    }
  }

  frame_regions_.clear();
  regions_.build(events, in_region_, *frame.x, record.index, frame_regions_, region_of_);
  for (RegionRecord& region : frame_regions_) {
    region.id = next_region_++;
    ++pair(region.kind, region.object_a, region.object_b).regions;
  }
  ended_.clear();
  tracks_.add_frame(frame.position, record.index, frame_regions_, ended_);
  record.regions = frame_regions_.size();

  trailer_.frames += 1;
  trailer_.events += record.collisions + record.intersections;
  trailer_.collisions += record.collisions;
  trailer_.vf += record.vf;
  trailer_.ee += record.ee;
  trailer_.uncertain += record.uncertain;
  trailer_.intersections += record.intersections;
  trailer_.regions += frame_regions_.size();

  if (writer_) writer_->write_frame(record);
  std::size_t listed = events.size();
  if (header_.settings.events != "all") {
    listed = 0;
  } else if (header_.settings.max_events > 0) {
    listed = std::min(listed, header_.settings.max_events - std::min(header_.settings.max_events, trailer_.listed));
  }
  if (writer_) {
    writer_->write_events(listed, [&](std::size_t i) {
      EventRecord out = event_record(events[i]);
      out.region = region_of_[i] == kNone ? kNone : frame_regions_[region_of_[i]].id;
      out.allowed = allowed_by_[i];
      return out;
    });
  }
  trailer_.listed += listed;
  trailer_.left_out += events.size() - listed;
  if (writer_) {
    for (const RegionRecord& region : frame_regions_) writer_->write_region(region);
  }
  end_tracks(ended_);
}

void ReportSink::end_tracks(std::vector<TrackRecord>& ended) {
  for (const TrackRecord& track : ended) {
    if (writer_) writer_->write_track(track);
    if (track.merged_into != kNone) continue;
    ++trailer_.tracks;
    ++pair(track.kind, track.object_a, track.object_b).tracks;
    auto& largest = trailer_.largest_tracks;
    auto larger = [](const TrackRecord& p, const TrackRecord& q) {
      return p.events != q.events ? p.events > q.events : p.id < q.id;
    };
    largest.insert(std::upper_bound(largest.begin(), largest.end(), track, larger), track);
    if (largest.size() > kLargestTracks) largest.pop_back();
  }
}

const Trailer& ReportSink::finish(std::string stages_json, std::string timing_json) {
  ended_.clear();
  tracks_.finish(ended_);
  end_tracks(ended_);
  trailer_.pairs.clear();
  for (const auto& [key, summary] : pairs_) trailer_.pairs.push_back(summary);
  Counts counts;
  counts.events = trailer_.events;
  counts.collisions = trailer_.collisions;
  counts.intersections = trailer_.intersections;
  counts.regions = trailer_.regions;
  counts.tracks = trailer_.tracks;
  trailer_.failed.clear();
  for (const FailedRule& failed : judge(rules_.rules().fail, counts)) {
    trailer_.failed.push_back(failed);
  }
  trailer_.pass = trailer_.failed.empty();
  trailer_.stages_json = std::move(stages_json);
  trailer_.timing_json = std::move(timing_json);
  if (writer_) writer_->write_trailer(trailer_);
  return trailer_;
}

}  // namespace snag::report
