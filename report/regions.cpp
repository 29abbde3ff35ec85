#include "report/regions.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "libcd/pipeline/event_objects.hpp"

namespace snag::report {

namespace {

// Below this many events or faces a loop runs on the calling thread: most
// groups are small, and a task costs more than their work.
constexpr std::size_t kEventsPerTask = 2048;
// The events of a frame are grouped in blocks of this many, each block's
// runs of one group listed on one thread.
constexpr std::size_t kEventsPerBlock = 16384;
// Words of the face marks (64 faces each) listed per task.
constexpr std::size_t kWordsPerTask = 256;

void grow(Bounds& bounds, const Vec3& p) {
  bounds.lo = {std::min(bounds.lo.x, p.x), std::min(bounds.lo.y, p.y), std::min(bounds.lo.z, p.z)};
  bounds.hi = {std::max(bounds.hi.x, p.x), std::max(bounds.hi.y, p.y), std::max(bounds.hi.z, p.z)};
}

Bounds empty_bounds() {
  const double inf = std::numeric_limits<double>::infinity();
  return {{inf, inf, inf}, {-inf, -inf, -inf}};
}

// Lowers `value` to `candidate` if that is smaller.
void lower_to(std::atomic<std::size_t>& value, std::size_t candidate) {
  std::size_t seen = value.load(std::memory_order_relaxed);
  while (candidate < seen && !value.compare_exchange_weak(seen, candidate, std::memory_order_relaxed)) {
  }
}

// A region's events added up one after the other, in event order (the
// centroid's sum is rounded as it always was).
struct RegionSums {
  std::size_t events = 0;
  Vec3 position_sum{0, 0, 0};
  Bounds bounds = empty_bounds();
  double toi = std::numeric_limits<double>::infinity();
};

}  // namespace

std::pair<std::size_t, std::size_t> event_objects(const Scene& scene, const Event& e) {
  const auto [a, b] = element_objects(scene, e);
  return {std::min(a, b), std::max(a, b)};
}

RegionBuilder::RegionBuilder(const Scene& scene)
    : scene_(scene),
      face_marks_(new std::atomic<std::uint64_t>[(scene.triangle_count() + 63) / 64]()),
      vertex_face_(new std::atomic<Index>[scene.vertex_count()]()),
      face_sets_(scene.triangle_count()),
      first_of_root_(new std::atomic<std::size_t>[scene.triangle_count()]()),
      region_of_root_(scene.triangle_count(), kNone) {
  touched_.reserve(scene.triangle_count());  // listing the marked faces then allocates nothing
  const auto& triangles = scene.triangles();
  vertex_face_start_.assign(scene.vertex_count() + 1, 0);
  for (const Triangle& t : triangles)
    for (Index v : t) ++vertex_face_start_[v + 1];
  std::partial_sum(vertex_face_start_.begin(), vertex_face_start_.end(), vertex_face_start_.begin());
  vertex_faces_.resize(vertex_face_start_.back());
  std::vector<Index> fill(vertex_face_start_.begin(), vertex_face_start_.end() - 1);
  for (Index f = 0; f < triangles.size(); ++f)
    for (Index v : triangles[f]) vertex_faces_[fill[v]++] = f;
  // The faces on each edge, in the order of the faces around its first end.
  const auto& edges = scene.edges();
  edge_face_start_.assign(edges.size() + 1, 0);
  for (Index e = 0; e < edges.size(); ++e) {
    const Edge& edge = edges[e];
    for (Index k = vertex_face_start_[edge[0]]; k < vertex_face_start_[edge[0] + 1]; ++k) {
      const Triangle& t = triangles[vertex_faces_[k]];
      if (t[0] == edge[1] || t[1] == edge[1] || t[2] == edge[1]) edge_faces_.push_back(vertex_faces_[k]);
    }
    edge_face_start_[e + 1] = static_cast<Index>(edge_faces_.size());
  }
}

template <class Visit>
void RegionBuilder::for_each_event_face(const Event& e, Visit visit) const {
  auto around_vertex = [&](Index v) {
    for (Index k = vertex_face_start_[v]; k < vertex_face_start_[v + 1]; ++k) visit(vertex_faces_[k]);
  };
  auto on_edge = [&](Index id) {
    for (Index k = edge_face_start_[id]; k < edge_face_start_[id + 1]; ++k) visit(edge_faces_[k]);
  };
  if (e.kind == EventKind::kIntersection) {
    visit(e.a);
    visit(e.b);
  } else if (e.type == ContactType::kVertexFace) {
    visit(e.b);
    around_vertex(e.a);
  } else {
    on_edge(e.a);
    on_edge(e.b);
  }
}

// The first face for_each_event_face visits: every edge of a scene lies on a face.
Index RegionBuilder::first_face(const Event& e) const {
  if (e.kind == EventKind::kIntersection) return e.a;
  if (e.type == ContactType::kVertexFace) return e.b;
  const Index on_a = edge_face_start_[e.a];
  return on_a < edge_face_start_[e.a + 1] ? edge_faces_[on_a] : edge_faces_[edge_face_start_[e.b]];
}

// A face for_each_event_face visits of the event's second element (the
// first face around the vertex of a vertex-face pair, the first face on
// edge b).
Index RegionBuilder::second_face(const Event& e) const {
  if (e.kind == EventKind::kIntersection) return e.b;
  if (e.type == ContactType::kVertexFace) {  // a vertex on no face (a loose one) joins nothing
    const Index around = vertex_face_start_[e.a];
    return around < vertex_face_start_[e.a + 1] ? vertex_faces_[around] : e.b;
  }
  return edge_faces_[edge_face_start_[e.b]];
}

void RegionBuilder::join_faces(const std::vector<Event>& events, const std::vector<std::size_t>& group,
                               std::size_t object_a, std::size_t object_b) {
  const auto& triangles = scene_.triangles();
  const tbb::blocked_range<std::size_t> all_events(0, group.size(), kEventsPerTask);
  // One face of each element of each event, kept so that the passes after
  // this one read 8 bytes per event instead of the event; every face of
  // every event marked (a word of 64 faces is read before it is written, so
  // that a face marked already costs no atomic write).
  event_first_face_.resize(group.size());
  event_second_face_.resize(group.size());
  tbb::parallel_for(all_events, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const Event& e = events[group[k]];
      event_first_face_[k] = first_face(e);
      event_second_face_[k] = second_face(e);
      for_each_event_face(e, [&](Index f) {
        std::atomic<std::uint64_t>& word = face_marks_[f / 64];
        const std::uint64_t bit = std::uint64_t{1} << (f % 64);
        if ((word.load(std::memory_order_relaxed) & bit) == 0) word.fetch_or(bit, std::memory_order_relaxed);
      });
    }
  });
  // The marked faces, listed in ascending order and unmarked. An event's
  // faces lie on the group's two objects, so only their words are read.
  // Each listed face becomes a set of its own, and each of its vertices
  // keeps one of the group's faces around it.
  const std::size_t a_begin = scene_.triangle_offset(object_a) / 64;
  const std::size_t a_end = (scene_.triangle_offset(object_a + 1) + 63) / 64;
  const std::size_t b_begin = std::max<std::size_t>(a_end, scene_.triangle_offset(object_b) / 64);
  const std::size_t b_end = std::max<std::size_t>(b_begin, (scene_.triangle_offset(object_b + 1) + 63) / 64);
  const std::size_t words = (a_end - a_begin) + (b_end - b_begin);
  auto word_at = [&](std::size_t w) { return w < a_end - a_begin ? a_begin + w : b_begin + (w - (a_end - a_begin)); };
  const std::size_t tasks = (words + kWordsPerTask - 1) / kWordsPerTask;
  marked_before_.assign(tasks + 1, 0);
  tbb::parallel_for(std::size_t{0}, tasks, [&](std::size_t t) {
    std::size_t marked = 0;
    for (std::size_t w = t * kWordsPerTask; w < std::min(words, (t + 1) * kWordsPerTask); ++w)
      marked += static_cast<std::size_t>(__builtin_popcountll(face_marks_[word_at(w)].load(std::memory_order_relaxed)));
    marked_before_[t + 1] = marked;
  });
  std::partial_sum(marked_before_.begin(), marked_before_.end(), marked_before_.begin());
  touched_.resize(marked_before_[tasks]);  // within the room reserved for every face
  tbb::parallel_for(std::size_t{0}, tasks, [&](std::size_t t) {
    std::size_t at = marked_before_[t];
    for (std::size_t w = t * kWordsPerTask; w < std::min(words, (t + 1) * kWordsPerTask); ++w) {
      std::atomic<std::uint64_t>& word = face_marks_[word_at(w)];
      for (std::uint64_t bits = word.load(std::memory_order_relaxed); bits != 0; bits &= bits - 1) {
        const Index f = static_cast<Index>(64 * word_at(w) + static_cast<std::size_t>(__builtin_ctzll(bits)));
        touched_[at++] = f;
        face_sets_.reset(f);
        for (Index v : triangles[f]) vertex_face_[v].store(f, std::memory_order_relaxed);
      }
      word.store(0, std::memory_order_relaxed);
    }
  });
  // The faces of one event are one region; so are faces that share a vertex.
  // The faces around a vertex, or on an edge, share that vertex: of an
  // event's faces, only one of each element's needs joining here.
  tbb::parallel_for(all_events, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) face_sets_.unite(event_first_face_[k], event_second_face_[k]);
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, touched_.size(), kEventsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k < range.end(); ++k) {
                        const Index f = touched_[k];
                        for (Index v : triangles[f])
                          face_sets_.unite(f, vertex_face_[v].load(std::memory_order_relaxed));
                      }
                    });
}

void RegionBuilder::group_events(const std::vector<Event>& events, const std::vector<char>& in_region,
                                 std::map<GroupKey, std::vector<std::size_t>>& groups) const {
  // Each block lists its runs of events of one group (the events of a group
  // come in long runs); the runs then take their places in their groups'
  // lists in event order, and are written there on all threads.
  struct Run {
    GroupKey key;
    std::size_t begin, end;
    std::vector<std::size_t>* list;
    std::size_t at;
  };
  const std::size_t blocks = (events.size() + kEventsPerBlock - 1) / kEventsPerBlock;
  std::vector<std::vector<Run>> block_runs(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
    std::vector<Run>& runs = block_runs[block];
    const std::size_t end = std::min(events.size(), (block + 1) * kEventsPerBlock);
    for (std::size_t i = block * kEventsPerBlock; i < end; ++i) {
      if (!in_region[i]) continue;
      const auto [a, b] = event_objects(scene_, events[i]);
      const GroupKey key{static_cast<int>(events[i].kind), a, b};
      if (runs.empty() || runs.back().end != i || runs.back().key != key) runs.push_back({key, i, i, nullptr, 0});
      runs.back().end = i + 1;
    }
  });
  for (std::vector<Run>& runs : block_runs) {
    for (Run& run : runs) {
      run.list = &groups[run.key];
      run.at = run.list->size();
      run.list->resize(run.at + (run.end - run.begin));
    }
  }
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
    for (const Run& run : block_runs[block])
      std::iota(run.list->begin() + static_cast<std::ptrdiff_t>(run.at),
                run.list->begin() + static_cast<std::ptrdiff_t>(run.at + (run.end - run.begin)), run.begin);
  });
}

void RegionBuilder::add_regions(const std::vector<Event>& events, const std::vector<std::size_t>& group,
                                const GroupKey& key, const std::vector<Vec3>& x, std::size_t frame,
                                std::vector<RegionRecord>& regions, std::vector<std::size_t>& region_of,
                                std::vector<std::size_t>& first_event) {
  const EventKind kind = static_cast<EventKind>(std::get<0>(key));
  const std::size_t object_a = std::get<1>(key), object_b = std::get<2>(key);
  const tbb::blocked_range<std::size_t> all_events(0, group.size(), kEventsPerTask);
  const tbb::blocked_range<std::size_t> all_faces(0, touched_.size(), kEventsPerTask);
  // Roots after every join: the same for any number of threads. Each set's
  // first event is the smallest index of its events in the group.
  event_root_.resize(group.size());
  touched_root_.resize(touched_.size());
  tbb::parallel_for(all_faces, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      touched_root_[k] = face_sets_.find(touched_[k]);
      first_of_root_[touched_[k]].store(kNone, std::memory_order_relaxed);
    }
  });
  tbb::parallel_for(all_events, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      event_root_[k] = face_sets_.find(event_first_face_[k]);
      lower_to(first_of_root_[event_root_[k]], k);
    }
  });
  // One region per set (every set holds an event's faces), in the order of
  // its first event.
  std::vector<std::pair<std::size_t, Index>> sets;  // first event, root
  for (std::size_t k = 0; k < touched_.size(); ++k) {
    if (touched_root_[k] == touched_[k])
      sets.emplace_back(first_of_root_[touched_[k]].load(std::memory_order_relaxed), touched_[k]);
  }
  std::sort(sets.begin(), sets.end());
  const std::size_t first_region = regions.size();
  for (const auto& [first, root] : sets) {
    region_of_root_[root] = regions.size();
    RegionRecord region;
    region.kind = kind;
    region.object_a = object_a;
    region.object_b = object_b;
    region.frame = frame;
    region.bounds = empty_bounds();
    region.toi = std::numeric_limits<double>::infinity();
    regions.push_back(std::move(region));
    first_event.push_back(group[first]);
  }
  // Each event's region, position and time of impact, gathered on all
  // threads; then each region's events added up in event order on this one,
  // from the gathered 40 bytes an event instead of the event.
  event_region_.resize(group.size());
  event_place_.resize(group.size());
  tbb::parallel_for(all_events, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const Event& e = events[group[k]];
      event_region_[k] = region_of_root_[event_root_[k]];
      region_of[group[k]] = event_region_[k];
      event_place_[k] = {e.position, static_cast<double>(e.frame) + e.toi_lo};
    }
  });
  std::vector<RegionSums> sums(sets.size());
  for (std::size_t k = 0; k < group.size(); ++k) {
    RegionSums& sum = sums[event_region_[k] - first_region];
    const EventPlace& place = event_place_[k];
    ++sum.events;
    sum.position_sum = sum.position_sum + place.position;
    if (kind == EventKind::kCollision) {
      grow(sum.bounds, place.position);
      sum.toi = std::min(sum.toi, place.toi);
    }
  }
  for (std::size_t r = 0; r < sums.size(); ++r) {
    RegionRecord& region = regions[first_region + r];
    region.events = sums[r].events;
    region.centroid = sums[r].position_sum;
    region.bounds = sums[r].bounds;
    region.toi = sums[r].toi;
  }
  // Each face's region (its root's) and, for intersections,
  // the box of its corners, on all threads; then the faces listed in
  // ascending order on this one, so that each region's lists come sorted,
  // and its box grown by theirs (the same box as corner by corner).
  const bool face_boxes = kind == EventKind::kIntersection;
  touched_region_.resize(touched_.size());
  touched_box_.resize(face_boxes ? touched_.size() : 0);
  tbb::parallel_for(all_faces, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      touched_region_[k] = region_of_root_[touched_root_[k]];
      if (!face_boxes) continue;
      Bounds box = empty_bounds();
      for (Index v : scene_.triangles()[touched_[k]]) grow(box, x[v]);
      touched_box_[k] = box;
    }
  });
  const Index base_a = scene_.triangle_offset(object_a), base_b = scene_.triangle_offset(object_b);
  const Index end_a = scene_.triangle_offset(object_a + 1);
  for (std::size_t k = 0; k < touched_.size(); ++k) {
    RegionRecord& region = regions[touched_region_[k]];
    const Index f = touched_[k];
    if (f >= base_a && f < end_a) {
      region.faces_a.push_back(f - base_a);
    } else {
      region.faces_b.push_back(f - base_b);
    }
    if (face_boxes) {
      grow(region.bounds, touched_box_[k].lo);
      grow(region.bounds, touched_box_[k].hi);
    }
  }
}

void RegionBuilder::build(const std::vector<Event>& events, const std::vector<char>& in_region,
                          const std::vector<Vec3>& x, std::size_t frame, std::vector<RegionRecord>& regions,
                          std::vector<std::size_t>& region_of) {
  region_of.assign(events.size(), kNone);
  std::map<GroupKey, std::vector<std::size_t>> groups;
  group_events(events, in_region, groups);
  const std::size_t first_region = regions.size();
  std::vector<std::size_t> first_event;  // of each new region
  for (const auto& [key, group] : groups) {
    join_faces(events, group, std::get<1>(key), std::get<2>(key));
    add_regions(events, group, key, x, frame, regions, region_of, first_event);
  }
  // Order the frame's regions by their first event, so that ids follow the event order.
  const std::size_t count = regions.size() - first_region;
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return first_event[p] < first_event[q]; });
  std::vector<std::size_t> new_index(count);
  std::vector<RegionRecord> sorted;
  sorted.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    new_index[order[k]] = first_region + k;
    sorted.push_back(std::move(regions[first_region + order[k]]));
  }
  for (std::size_t k = 0; k < count; ++k) {
    RegionRecord& region = sorted[k];
    region.face_count = region.faces_a.size() + region.faces_b.size();
    region.centroid = (1.0 / static_cast<double>(region.events)) * region.centroid;
    regions[first_region + k] = std::move(region);
  }
  for (std::size_t& r : region_of)
    if (r != kNone) r = new_index[r - first_region];
}

TrackBuilder::TrackBuilder(const Scene& scene) : scene_(scene) {}

TrackBuilder::FaceKey TrackBuilder::key(const RegionRecord& r, std::size_t object, std::size_t local_face) const {
  const std::size_t objects = scene_.objects().size();
  const std::uint64_t pair = r.object_a * objects + r.object_b;
  const std::uint64_t face = scene_.triangle_offset(object) + local_face;
  return ((pair * 2 + (r.kind == EventKind::kCollision ? 1 : 0)) << 32) | face;
}

void TrackBuilder::tracks_touched(const RegionRecord& region, std::size_t object, const std::vector<std::size_t>& faces,
                                  std::vector<std::size_t>& tracks) const {
  // A region's faces ascend, and so do their keys: each search goes on from
  // where the last one ended, in steps that double (a galloping search), so
  // that the faces of a region cost little more than one pass over them.
  auto from = last_faces_.begin();
  const auto end = last_faces_.end();
  for (std::size_t f : faces) {
    const FaceKey k = key(region, object, f);
    std::ptrdiff_t step = 1;  // everything before `from` is below k
    while (step < end - from && from[step].first < k) {
      from += step;
      step *= 2;
    }
    const auto bound = step < end - from ? from + step + 1 : end;
    from = std::lower_bound(from, bound, k, [](const auto& entry, FaceKey key) { return entry.first < key; });
    if (from != end && from->first == k) tracks.push_back(from->second);
  }
}

void TrackBuilder::add_frame(std::size_t position, std::size_t frame, std::vector<RegionRecord>& regions,
                             std::vector<TrackRecord>& ended) {
  const std::size_t first_ended = ended.size();
  const bool consecutive = last_position_ != kNone && position == last_position_ + 1;
  if (!consecutive) last_faces_.clear();
  last_position_ = position;

  // The tracks of the last frame that each region shares a face with.
  std::vector<std::vector<std::size_t>> touched(regions.size());
  std::map<std::size_t, std::size_t> parent;  // union-find over touched track ids
  auto find = [&](std::size_t t) {
    while (parent[t] != t) t = parent[t];
    return t;
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, regions.size()), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t r = range.begin(); r < range.end(); ++r) {
      tracks_touched(regions[r], regions[r].object_a, regions[r].faces_a, touched[r]);
      tracks_touched(regions[r], regions[r].object_b, regions[r].faces_b, touched[r]);
      std::sort(touched[r].begin(), touched[r].end());
      touched[r].erase(std::unique(touched[r].begin(), touched[r].end()), touched[r].end());
    }
  });
  for (std::size_t r = 0; r < regions.size(); ++r) {
    for (std::size_t t : touched[r]) parent.emplace(t, t);
    for (std::size_t t : touched[r]) {
      const std::size_t a = find(touched[r].front()), b = find(t);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // Tracks that joined another: the smallest id of each class goes on with the others' counts.
  for (auto& [t, p] : parent) {
    const std::size_t root = find(t);
    if (root == t) continue;
    TrackRecord& merged = open_.at(t);
    TrackRecord& survivor = open_.at(root);
    merged.merged_into = root;
    survivor.first_frame = std::min(survivor.first_frame, merged.first_frame);
    survivor.frames = std::max(survivor.frames, merged.frames);
    survivor.regions += merged.regions;
    survivor.events += merged.events;
    if (merged.max_faces > survivor.max_faces) {
      survivor.max_faces = merged.max_faces;
      survivor.worst_frame = merged.worst_frame;
      survivor.centroid = merged.centroid;
    }
    grow(survivor.bounds, merged.bounds.lo);
    grow(survivor.bounds, merged.bounds.hi);
    survivor.toi = std::min(survivor.toi, merged.toi);
  }
  std::map<std::size_t, TrackRecord> going_on;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    RegionRecord& region = regions[r];
    std::size_t id = 0;
    if (touched[r].empty()) {
      id = next_id_++;
      TrackRecord track;
      track.id = id;
      track.kind = region.kind;
      track.object_a = region.object_a;
      track.object_b = region.object_b;
      track.first_frame = frame;
      track.bounds = empty_bounds();
      track.toi = std::numeric_limits<double>::infinity();
      going_on.emplace(id, track);
    } else {
      id = find(touched[r].front());
      if (!going_on.count(id)) {
        TrackRecord track = open_.at(id);
        ++track.frames;
        going_on.emplace(id, track);
      }
    }
    region.track = id;
    TrackRecord& track = going_on.at(id);
    if (track.frames == 0) track.frames = 1;
    track.last_frame = frame;
    ++track.regions;
    track.events += region.events;
    const std::size_t faces = region.faces_a.size() + region.faces_b.size();
    if (faces > track.max_faces) {
      track.max_faces = faces;
      track.worst_frame = frame;
      track.centroid = region.centroid;
    }
    grow(track.bounds, region.bounds.lo);
    grow(track.bounds, region.bounds.hi);
    if (region.kind == EventKind::kCollision) track.toi = std::min(track.toi, region.toi);
  }
  for (auto& [id, track] : open_)
    if (!going_on.count(id)) ended.push_back(track);
  std::sort(ended.begin() + static_cast<std::ptrdiff_t>(first_ended), ended.end(),
            [](const TrackRecord& p, const TrackRecord& q) { return p.id < q.id; });
  open_ = std::move(going_on);

  last_faces_.clear();
  for (const RegionRecord& region : regions) {
    for (std::size_t f : region.faces_a) last_faces_.emplace_back(key(region, region.object_a, f), region.track);
    for (std::size_t f : region.faces_b) last_faces_.emplace_back(key(region, region.object_b, f), region.track);
  }
  tbb::parallel_sort(last_faces_.begin(), last_faces_.end());
}

void TrackBuilder::finish(std::vector<TrackRecord>& ended) {
  for (auto& [id, track] : open_) ended.push_back(track);
  open_.clear();
  last_faces_.clear();
  last_position_ = kNone;
}

}  // namespace snag::report
