#include "report/report_sink.hpp"

#include <algorithm>
#include <exception>
#include <stdexcept>

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
      tracks_(scene) {
  trailer_.allow_counts.assign(rules_.rules().allow.size(), 0);
  if (writer_) writer_->write_header(header_);
  digesters_made_ = joiner_.run([this] {
    faces_ = std::make_shared<const FaceAdjacency>(scene_);
    std::vector<std::unique_ptr<FrameDigester>> made;
    for (std::size_t k = 0; k < kFramesAtOnce; ++k)
      made.push_back(std::make_unique<FrameDigester>(scene_, rules_, faces_));
    std::lock_guard<std::mutex> lock(pool_mutex_);
    for (auto& digester : made) free_digesters_.push_back(std::move(digester));
  });
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

ReportSink::~ReportSink() {
  if (joining_.valid()) joining_.wait();
}

void ReportSink::wait_for_join() {
  if (!joining_.valid()) return;
  std::exception_ptr error;
  try {
    joining_.get();
  } catch (...) {
    error = std::current_exception();
  }
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    free_digests_.push_back(std::move(joined_));
  }
  if (error) std::rethrow_exception(error);
}

void ReportSink::prepare(ScannedFrame& frame) {
  if (redecide_ && frame.x_next) redecide_(*frame.x, *frame.x_next, *frame.events);
  digesters_made_.get();  // rethrows what making them threw; faces_ is set after it
  std::unique_ptr<FrameDigester> digester;
  std::unique_ptr<FrameDigest> digest;
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    if (!free_digesters_.empty()) {
      digester = std::move(free_digesters_.back());
      free_digesters_.pop_back();
    }
    if (!free_digests_.empty()) {
      digest = std::move(free_digests_.back());
      free_digests_.pop_back();
    }
  }
  if (!digester) digester = std::make_unique<FrameDigester>(scene_, rules_, faces_);  // more frames at once than made
  if (!digest) digest = std::make_unique<FrameDigest>();
  digester->digest(frame, *digest);
  std::lock_guard<std::mutex> lock(pool_mutex_);
  free_digesters_.push_back(std::move(digester));
  prepared_[frame.position] = std::move(digest);
}

std::unique_ptr<FrameDigest> ReportSink::take_prepared(std::size_t position) {
  std::lock_guard<std::mutex> lock(pool_mutex_);
  const auto it = prepared_.find(position);
  if (it == prepared_.end()) return nullptr;
  std::unique_ptr<FrameDigest> digest = std::move(it->second);
  prepared_.erase(it);
  return digest;
}

void ReportSink::frame(ScannedFrame& frame) {
  std::unique_ptr<FrameDigest> digest = take_prepared(frame.position);
  if (!digest) {  // not prepared on the scan's sink threads
    prepare(frame);
    digest = take_prepared(frame.position);
  }
  wait_for_join();
  // Listed events are read from the scan's list, which is the scan's again
  // once this returns.
  if (events_to_list(header_.settings, trailer_.listed, digest->kept) > 0) {
    join_now(*digest);
    std::lock_guard<std::mutex> lock(pool_mutex_);
    free_digests_.push_back(std::move(digest));
    return;
  }
  joined_ = std::move(digest);
  joining_ = joiner_.run([this, joined = joined_.get()] { join_arena_.execute([&] { join_now(*joined); }); });
}

void ReportSink::join(FrameDigest& digest) {
  wait_for_join();
  join_now(digest);
}

void ReportSink::join_now(FrameDigest& digest) {
  const std::size_t listed = events_to_list(header_.settings, trailer_.listed, digest.kept);
  if (listed > digest.listable) throw std::logic_error("a frame's digest lacks events that the report lists");
  const FrameRecord& record = digest.record;
  for (const PairCounts& counts : digest.pairs) {
    PairSummary& summary = pair(counts.kind, counts.object_a, counts.object_b);
    summary.events += counts.checked;
    summary.allowed += counts.allowed;
    if (counts.checked == 0) continue;
    ++summary.frames;
    if (counts.checked > summary.worst_frame_events) {
      summary.worst_frame_events = counts.checked;
      summary.worst_frame = record.index;
    }
  }
  std::vector<RegionRecord>& regions = digest.regions;
  for (RegionRecord& region : regions) {
    region.id = next_region_++;
    ++pair(region.kind, region.object_a, region.object_b).regions;
  }
  ended_.clear();
  tracks_.add_frame(record.position, record.index, regions, ended_);

  trailer_.frames += 1;
  trailer_.events += record.collisions + record.intersections;
  trailer_.collisions += record.collisions;
  trailer_.vf += record.vf;
  trailer_.ee += record.ee;
  trailer_.uncertain += record.uncertain;
  trailer_.intersections += record.intersections;
  trailer_.regions += regions.size();
  trailer_.allowed += record.allowed;
  trailer_.not_checked += digest.not_checked;
  trailer_.neighbourhood += digest.neighbourhood;
  for (std::size_t rule = 0; rule < digest.allow_counts.size(); ++rule) {
    trailer_.allow_counts[rule] += digest.allow_counts[rule];
  }

  if (writer_) writer_->write_frame(record);
  if (writer_) {
    writer_->write_events(listed, [&](std::size_t i) {
      EventRecord out = event_record(digest.events[i]);
      out.region = digest.region_of[i] == kNone ? kNone : regions[digest.region_of[i]].id;
      out.allowed = digest.allowed_by[i];
      return out;
    });
  }
  trailer_.listed += listed;
  trailer_.left_out += digest.kept - listed;
  if (writer_) {
    for (const RegionRecord& region : regions) writer_->write_region(region);
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
  wait_for_join();
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
