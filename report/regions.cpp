#include "report/regions.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
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
// Words of a bit set of marks (64 ids each) taken per task.
constexpr std::size_t kWordsPerTask = 32;

void grow(Bounds& bounds, const Vec3& p) {
  bounds.lo = {std::min(bounds.lo.x, p.x), std::min(bounds.lo.y, p.y), std::min(bounds.lo.z, p.z)};
  bounds.hi = {std::max(bounds.hi.x, p.x), std::max(bounds.hi.y, p.y), std::max(bounds.hi.z, p.z)};
}

// Grows `bounds` to hold `other` (either may be empty).
void grow(Bounds& bounds, const Bounds& other) {
  bounds.lo = {std::min(bounds.lo.x, other.lo.x), std::min(bounds.lo.y, other.lo.y), std::min(bounds.lo.z, other.lo.z)};
  bounds.hi = {std::max(bounds.hi.x, other.hi.x), std::max(bounds.hi.y, other.hi.y), std::max(bounds.hi.z, other.hi.z)};
}

Bounds empty_bounds() {
  const double inf = std::numeric_limits<double>::infinity();
  return {{inf, inf, inf}, {-inf, -inf, -inf}};
}

}  // namespace

std::pair<std::size_t, std::size_t> event_objects(const Scene& scene, const Event& e) {
  const auto [a, b] = element_objects(scene, e);
  return {std::min(a, b), std::max(a, b)};
}

RegionBuilder::Lane::Lane(const Scene& scene, std::size_t index)
    : face_marks(new std::atomic<std::uint64_t>[(scene.triangle_count() + 63) / 64]()),
      vertex_marks(new std::atomic<std::uint64_t>[(scene.vertex_count() + 63) / 64]()),
      edge_marks(new std::atomic<std::uint64_t>[(scene.edges().size() + 63) / 64]()),
      face_sets(scene.triangle_count() + scene.vertex_count()),
      region_of_root(new std::atomic<std::size_t>[scene.triangle_count()]),
      tag(index << kLaneShift) {
  for (std::size_t f = 0; f < scene.triangle_count(); ++f) region_of_root[f].store(kNone, std::memory_order_relaxed);
  touched.reserve(scene.triangle_count());  // listing the marked faces then allocates nothing
}

FaceAdjacency::FaceAdjacency(const Scene& scene) {
  const auto& triangles = scene.triangles();
  vertex_face_start.assign(scene.vertex_count() + 1, 0);
  for (const Triangle& t : triangles)
    for (Index v : t) ++vertex_face_start[v + 1];
  std::partial_sum(vertex_face_start.begin(), vertex_face_start.end(), vertex_face_start.begin());
  vertex_faces.resize(vertex_face_start.back());
  std::vector<Index> fill(vertex_face_start.begin(), vertex_face_start.end() - 1);
  for (Index f = 0; f < triangles.size(); ++f)
    for (Index v : triangles[f]) vertex_faces[fill[v]++] = f;
  // The faces on each edge, in the order of the faces around its first end.
  const auto& edges = scene.edges();
  edge_face_start.assign(edges.size() + 1, 0);
  for (Index e = 0; e < edges.size(); ++e) {
    const Edge& edge = edges[e];
    for (Index k = vertex_face_start[edge[0]]; k < vertex_face_start[edge[0] + 1]; ++k) {
      const Triangle& t = triangles[vertex_faces[k]];
      if (t[0] == edge[1] || t[1] == edge[1] || t[2] == edge[1]) edge_faces.push_back(vertex_faces[k]);
    }
    edge_face_start[e + 1] = static_cast<Index>(edge_faces.size());
  }
}

RegionBuilder::RegionBuilder(const Scene& scene, std::shared_ptr<const FaceAdjacency> faces)
    : scene_(scene), faces_(std::move(faces)) {
  if (scene.triangle_count() + scene.vertex_count() > std::numeric_limits<Index>::max())
    throw std::length_error("a scene's faces and vertices together outnumber the region builder's ids");
  if (scene.objects().size() > std::size_t{0x7fffffff})
    throw std::length_error("a scene's objects outnumber the region builder's group words");
  if (!faces_) faces_ = std::make_shared<const FaceAdjacency>(scene);
}

namespace {

// Sets bit `id` of `words` (read before it is written, so that a bit set
// already costs no atomic write).
void mark(std::atomic<std::uint64_t>* words, std::size_t id) {
  std::atomic<std::uint64_t>& word = words[id / 64];
  const std::uint64_t bit = std::uint64_t{1} << (id % 64);
  if ((word.load(std::memory_order_relaxed) & bit) == 0) word.fetch_or(bit, std::memory_order_relaxed);
}

// The words of a bit set (64 ids each) that hold two objects' ids, [a_begin,
// a_end) and [b_begin, b_end), numbered 0 .. size() - 1.
class ObjectWords {
 public:
  ObjectWords(std::size_t a_begin, std::size_t a_end, std::size_t b_begin, std::size_t b_end)
      : a_begin_(a_begin / 64),
        a_end_((a_end + 63) / 64),
        b_begin_(std::max(a_end_, b_begin / 64)),
        b_end_(std::max(b_begin_, (b_end + 63) / 64)) {}
  std::size_t size() const { return (a_end_ - a_begin_) + (b_end_ - b_begin_); }
  std::size_t operator[](std::size_t w) const {
    return w < a_end_ - a_begin_ ? a_begin_ + w : b_begin_ + (w - (a_end_ - a_begin_));
  }

 private:
  std::size_t a_begin_, a_end_, b_begin_, b_end_;
};

// Calls visit(id) for every set bit of the words `words` numbers in [begin,
// end), in ascending order, and clears them.
template <class Visit>
void take_marks(std::atomic<std::uint64_t>* bits, const ObjectWords& words, std::size_t begin, std::size_t end,
                Visit visit) {
  for (std::size_t w = begin; w < end; ++w) {
    std::atomic<std::uint64_t>& word = bits[words[w]];
    for (std::uint64_t set = word.load(std::memory_order_relaxed); set != 0; set &= set - 1)
      visit(static_cast<Index>(64 * words[w] + static_cast<std::size_t>(__builtin_ctzll(set))));
    word.store(0, std::memory_order_relaxed);
  }
}

}  // namespace

void RegionBuilder::join_faces(Lane& lane, const std::vector<Event>& events, const std::vector<std::size_t>& group,
                               std::size_t object_a, std::size_t object_b) const {
  const auto& triangles = scene_.triangles();
  const auto& edges = scene_.edges();
  const FaceAdjacency& faces = *faces_;
  lane.face_sets.clear();
  // One pass over the group's events, the only one that reads them: the
  // elements of each event marked (a face, a vertex for the faces around
  // it, an edge for the faces on it), the two sets the event joins kept (a
  // vertex's set, once its faces are joined with it below, holds them; an
  // edge's faces hold its first end), and what the regions need of the
  // event, its position and time, in arrays of their own (the positions
  // are added up on one thread, below, and read alone). A vertex on no face
  // (a loose one) joins nothing.
  lane.event_first_set.resize(group.size());
  lane.event_second_set.resize(group.size());
  lane.event_position.resize(group.size());
  lane.event_toi.resize(group.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, group.size(), kEventsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k < range.end(); ++k) {
                        const Event& e = events[group[k]];
                        lane.event_position[k] = e.position;
                        lane.event_toi[k] = static_cast<double>(e.frame) + e.toi_lo;
                        Index first = e.a, second = e.b;
                        if (e.kind == EventKind::kIntersection) {
                          mark(lane.face_marks.get(), e.a);
                          mark(lane.face_marks.get(), e.b);
                        } else if (e.type == ContactType::kVertexFace) {
                          mark(lane.face_marks.get(), e.b);
                          mark(lane.vertex_marks.get(), e.a);
                          first = e.b;
                          const bool loose = faces.vertex_face_start[e.a] == faces.vertex_face_start[e.a + 1];
                          second = loose ? e.b : vertex_set(e.a);
                        } else {
                          mark(lane.edge_marks.get(), e.a);
                          mark(lane.edge_marks.get(), e.b);
                          first = vertex_set(edges[e.a][0]);
                          second = vertex_set(edges[e.b][0]);
                        }
                        lane.event_first_set[k] = first;
                        lane.event_second_set[k] = second;
                      }
                    });
  // The faces around each marked vertex and on each marked edge marked. An
  // event's elements lie on the group's two objects, so only their words
  // are read.
  const ObjectWords face_words(scene_.triangle_offset(object_a), scene_.triangle_offset(object_a + 1),
                               scene_.triangle_offset(object_b), scene_.triangle_offset(object_b + 1));
  const ObjectWords vertex_words(scene_.vertex_offset(object_a), scene_.vertex_offset(object_a + 1),
                                 scene_.vertex_offset(object_b), scene_.vertex_offset(object_b + 1));
  const ObjectWords edge_words(scene_.edge_offset(object_a), scene_.edge_offset(object_a + 1),
                               scene_.edge_offset(object_b), scene_.edge_offset(object_b + 1));
  const std::size_t vertex_tasks = (vertex_words.size() + kWordsPerTask - 1) / kWordsPerTask;
  const std::size_t edge_tasks = (edge_words.size() + kWordsPerTask - 1) / kWordsPerTask;
  tbb::parallel_for(std::size_t{0}, vertex_tasks + edge_tasks, [&](std::size_t t) {
    if (t < vertex_tasks) {
      take_marks(lane.vertex_marks.get(), vertex_words, t * kWordsPerTask,
                 std::min(vertex_words.size(), (t + 1) * kWordsPerTask), [&](Index v) {
                   for (Index k = faces.vertex_face_start[v]; k < faces.vertex_face_start[v + 1]; ++k)
                     mark(lane.face_marks.get(), faces.vertex_faces[k]);
                 });
    } else {
      t -= vertex_tasks;
      take_marks(lane.edge_marks.get(), edge_words, t * kWordsPerTask,
                 std::min(edge_words.size(), (t + 1) * kWordsPerTask), [&](Index id) {
                   for (Index k = faces.edge_face_start[id]; k < faces.edge_face_start[id + 1]; ++k)
                     mark(lane.face_marks.get(), faces.edge_faces[k]);
                 });
    }
  });
  // The marked faces, listed in ascending order and unmarked. Faces that
  // share a vertex are one region: each listed face is joined with its
  // vertices' sets (after the faces' in the union-find, so that every
  // region's root is still its smallest face).
  const std::size_t tasks = (face_words.size() + kWordsPerTask - 1) / kWordsPerTask;
  lane.marked_before.assign(tasks + 1, 0);
  tbb::parallel_for(std::size_t{0}, tasks, [&](std::size_t t) {
    std::size_t marked = 0;
    for (std::size_t w = t * kWordsPerTask; w < std::min(face_words.size(), (t + 1) * kWordsPerTask); ++w)
      marked += static_cast<std::size_t>(
          __builtin_popcountll(lane.face_marks[face_words[w]].load(std::memory_order_relaxed)));
    lane.marked_before[t + 1] = marked;
  });
  std::partial_sum(lane.marked_before.begin(), lane.marked_before.end(), lane.marked_before.begin());
  lane.touched.resize(lane.marked_before[tasks]);  // within the room reserved for every face
  tbb::parallel_for(std::size_t{0}, tasks, [&](std::size_t t) {
    std::size_t at = lane.marked_before[t];
    take_marks(lane.face_marks.get(), face_words, t * kWordsPerTask,
               std::min(face_words.size(), (t + 1) * kWordsPerTask), [&](Index f) {
                 lane.touched[at++] = f;
                 for (Index v : triangles[f]) lane.face_sets.unite(f, vertex_set(v));
               });
  });
  // Each event's two sets joined, now that the faces of each region's
  // stretches of mesh are: most events find both in one set already, by
  // reading alone (root_of), and write nothing (an event with the sets of
  // the event before it is not looked at again).
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, group.size(), kEventsPerTask),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k < range.end(); ++k) {
          const Index first = lane.event_first_set[k], second = lane.event_second_set[k];
          if (k > range.begin() && first == lane.event_first_set[k - 1] && second == lane.event_second_set[k - 1])
            continue;
          if (lane.face_sets.root_of(first) != lane.face_sets.root_of(second)) lane.face_sets.unite(first, second);
        }
      });
}

void RegionBuilder::group_events(const std::vector<GroupWord>& group_of) {
  // Each block lists its runs of events of one group (the events of a group
  // come in long runs); the runs then take their places in their groups'
  // lists in event order, and are written there on all threads.
  struct Run {
    GroupWord word;
    std::size_t begin, end;
    std::vector<std::size_t>* list;
    std::size_t at;
  };
  for (auto& [key, list] : groups_) list.clear();  // the lists keep their room from frame to frame
  const std::size_t blocks = (group_of.size() + kEventsPerBlock - 1) / kEventsPerBlock;
  std::vector<std::vector<Run>> block_runs(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
    std::vector<Run>& runs = block_runs[block];
    const std::size_t end = std::min(group_of.size(), (block + 1) * kEventsPerBlock);
    for (std::size_t i = block * kEventsPerBlock; i < end; ++i) {
      const GroupWord word = group_of[i];
      if (word == kNoGroup) continue;
      if (runs.empty() || runs.back().end != i || runs.back().word != word) runs.push_back({word, i, i, nullptr, 0});
      runs.back().end = i + 1;
    }
  });
  for (std::vector<Run>& runs : block_runs) {
    for (Run& run : runs) {
      const GroupKey key{static_cast<int>(run.word >> 63 ? EventKind::kIntersection : EventKind::kCollision),
                         (run.word >> 32) & 0x7fffffffu, run.word & 0xffffffffu};
      run.list = &groups_[key];
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

void RegionBuilder::add_regions(Lane& lane, const std::vector<std::size_t>& group, const GroupKey& key,
                                const std::vector<Vec3>& x, std::size_t frame,
                                std::vector<std::size_t>& region_of) const {
  const EventKind kind = static_cast<EventKind>(std::get<0>(key));
  const std::size_t object_a = std::get<1>(key), object_b = std::get<2>(key);
  const std::size_t blocks = (group.size() + kEventsPerTask - 1) / kEventsPerTask;
  const tbb::blocked_range<std::size_t> all_faces(0, lane.touched.size(), kEventsPerTask);
  // The root of each event's set, once every join is done (the same for any
  // number of threads), and each root's first event: the smallest index of
  // its events, kept at the root, whose block lists the root when it is the
  // first to find it. A block takes the root of its last event for granted:
  // the events of a region come in long runs.
  lane.event_root.resize(group.size());
  lane.block_roots.resize(std::max(lane.block_roots.size(), blocks));
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
    std::vector<Index>& found = lane.block_roots[block];
    found.clear();
    Index last_root = 0;
    for (std::size_t k = block * kEventsPerTask; k < std::min(group.size(), (block + 1) * kEventsPerTask); ++k) {
      const Index root = lane.face_sets.root_of(lane.event_first_set[k]);  // no thread unites now
      lane.event_root[k] = root;
      if (k > block * kEventsPerTask && root == last_root) continue;
      last_root = root;
      std::atomic<std::size_t>& first = lane.region_of_root[root];
      std::size_t seen = first.load(std::memory_order_relaxed);
      while (k < seen && !first.compare_exchange_weak(seen, k, std::memory_order_relaxed)) {
      }
      if (seen == kNone) found.push_back(root);
    }
  });
  // One region per set (every set holds an event's faces), in the order of
  // their first events; each root then holds its region.
  const std::size_t first_region = lane.regions.size();
  lane.group_roots.clear();
  for (std::size_t block = 0; block < blocks; ++block)
    lane.group_roots.insert(lane.group_roots.end(), lane.block_roots[block].begin(), lane.block_roots[block].end());
  std::sort(lane.group_roots.begin(), lane.group_roots.end(), [&](Index p, Index q) {
    return lane.region_of_root[p].load(std::memory_order_relaxed) <
           lane.region_of_root[q].load(std::memory_order_relaxed);
  });
  for (const Index root : lane.group_roots) {
    RegionRecord record;
    record.kind = kind;
    record.object_a = object_a;
    record.object_b = object_b;
    record.frame = frame;
    record.bounds = empty_bounds();
    record.toi = std::numeric_limits<double>::infinity();
    lane.regions.push_back(std::move(record));
    lane.first_event.push_back(group[lane.region_of_root[root].load(std::memory_order_relaxed)]);
    lane.region_of_root[root].store(lane.regions.size() - 1, std::memory_order_relaxed);
  }
  auto region_of_event = [&](std::size_t k) {
    return lane.region_of_root[lane.event_root[k]].load(std::memory_order_relaxed);
  };
  // At once: each region's positions added up in event order on one thread
  // (the centroid's sum is rounded as it always was: the sum of a region is
  // one chain of additions, and one region often holds most of the events,
  // so that this chain is the longest serial work of a frame's regions);
  // each event's region, and each region's count, box and earliest time
  // over blocks of events (exact in any order), on all threads; each face's
  // region (its root's) and, for intersections, the box of its corners, on
  // all threads, then the faces listed in ascending order on one thread, so
  // that each region's lists come sorted, and its box grown by theirs (the
  // same box as corner by corner).
  const bool collisions = kind == EventKind::kCollision;
  const bool face_boxes = kind == EventKind::kIntersection;
  const std::size_t region_count = lane.group_roots.size();
  std::vector<Vec3> position_sums(region_count, Vec3{0, 0, 0});
  lane.block_sums.assign(blocks * region_count, RegionSums{0, empty_bounds(), std::numeric_limits<double>::infinity()});
  lane.touched_region.resize(lane.touched.size());
  lane.touched_box.resize(face_boxes ? lane.touched.size() : 0);
  tbb::parallel_invoke(
      [&] {
        // Run by run of events with one root (a region has one), each run
        // in a loop of nothing but the additions.
        for (std::size_t k = 0; k < group.size();) {
          const Index root = lane.event_root[k];
          std::size_t end = k + 1;
          while (end < group.size() && lane.event_root[end] == root) ++end;
          Vec3& region_sum = position_sums[lane.region_of_root[root].load(std::memory_order_relaxed) - first_region];
          Vec3 sum = region_sum;
          for (; k < end; ++k) sum = sum + lane.event_position[k];
          region_sum = sum;
        }
      },
      [&] {
        tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
          RegionSums* sums = &lane.block_sums[block * region_count];
          for (std::size_t k = block * kEventsPerTask; k < std::min(group.size(), (block + 1) * kEventsPerTask); ++k) {
            const std::size_t region = region_of_event(k);
            region_of[group[k]] = lane.tag | region;
            RegionSums& sum = sums[region - first_region];
            ++sum.events;
            if (!collisions) continue;
            grow(sum.bounds, lane.event_position[k]);
            sum.toi = std::min(sum.toi, lane.event_toi[k]);
          }
        });
      },
      [&] {
        tbb::parallel_for(all_faces, [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t k = range.begin(); k < range.end(); ++k) {
            lane.touched_region[k] =
                lane.region_of_root[lane.face_sets.root_of(lane.touched[k])].load(std::memory_order_relaxed);
            if (!face_boxes) continue;
            Bounds box = empty_bounds();
            for (Index v : scene_.triangles()[lane.touched[k]]) grow(box, x[v]);
            lane.touched_box[k] = box;
          }
        });
        const Index base_a = scene_.triangle_offset(object_a), base_b = scene_.triangle_offset(object_b);
        const Index end_a = scene_.triangle_offset(object_a + 1);
        for (std::size_t k = 0; k < lane.touched.size(); ++k) {
          RegionRecord& region = lane.regions[lane.touched_region[k]];
          const Index f = lane.touched[k];
          if (f >= base_a && f < end_a) {
            region.faces_a.push_back(f - base_a);
          } else {
            region.faces_b.push_back(f - base_b);
          }
          if (face_boxes) grow(region.bounds, lane.touched_box[k]);
        }
      });
  for (std::size_t r = 0; r < region_count; ++r) {
    RegionRecord& region = lane.regions[first_region + r];
    region.centroid = position_sums[r];
    for (std::size_t block = 0; block < blocks; ++block) {
      const RegionSums& sums = lane.block_sums[block * region_count + r];
      region.events += sums.events;
      grow(region.bounds, sums.bounds);
      region.toi = std::min(region.toi, sums.toi);
    }
  }
  for (const Index root : lane.group_roots) lane.region_of_root[root].store(kNone, std::memory_order_relaxed);
}

void RegionBuilder::build(const std::vector<Event>& events, const std::vector<char>& in_region,
                          const std::vector<Vec3>& x, std::size_t frame, std::vector<RegionRecord>& regions,
                          std::vector<std::size_t>& region_of) {
  group_of_.resize(events.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, events.size(), kEventsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        const auto [a, b] = event_objects(scene_, events[i]);
                        group_of_[i] = in_region[i] ? group_word(events[i].kind, a, b) : kNoGroup;
                      }
                    });
  build(events, group_of_, x, frame, regions, region_of);
}

void RegionBuilder::build(const std::vector<Event>& events, const std::vector<GroupWord>& group_of,
                          const std::vector<Vec3>& x, std::size_t frame, std::vector<RegionRecord>& regions,
                          std::vector<std::size_t>& region_of) {
  const tbb::blocked_range<std::size_t> all_events(0, events.size(), kEventsPerTask);
  region_of.resize(events.size());
  tbb::parallel_for(all_events, [&](const tbb::blocked_range<std::size_t>& range) {
    std::fill(region_of.begin() + static_cast<std::ptrdiff_t>(range.begin()),
              region_of.begin() + static_cast<std::ptrdiff_t>(range.end()), kNone);
  });
  group_events(group_of);
  // The groups are built at once, on lanes of their own (the passes over one
  // group keep few threads busy): largest first, each to the lane with the
  // fewest events so far.
  std::vector<const std::pair<const GroupKey, std::vector<std::size_t>>*> groups;
  for (const auto& entry : groups_)
    if (!entry.second.empty()) groups.push_back(&entry);
  std::stable_sort(groups.begin(), groups.end(),
                   [](const auto* p, const auto* q) { return p->second.size() > q->second.size(); });
  const std::size_t lane_count = std::min(kLanes, groups.size());
  while (lanes_.size() < lane_count) lanes_.push_back(std::make_unique<Lane>(scene_, lanes_.size()));
  std::vector<std::vector<const std::pair<const GroupKey, std::vector<std::size_t>>*>> lane_groups(lane_count);
  std::vector<std::size_t> lane_events(lane_count, 0);
  for (const auto* group : groups) {
    const std::size_t l =
        static_cast<std::size_t>(std::min_element(lane_events.begin(), lane_events.end()) - lane_events.begin());
    lane_groups[l].push_back(group);
    lane_events[l] += group->second.size();
  }
  tbb::parallel_for(std::size_t{0}, lane_count, [&](std::size_t l) {
    Lane& lane = *lanes_[l];
    lane.regions.clear();
    lane.first_event.clear();
    for (const auto* group : lane_groups[l]) {
      const auto& [key, events_of_group] = *group;
      join_faces(lane, events, events_of_group, std::get<1>(key), std::get<2>(key));
      add_regions(lane, events_of_group, key, x, frame, region_of);
    }
  });
  // The lanes' regions in the order of their first event, so that ids follow
  // the event order.
  const std::size_t first_region = regions.size();
  std::vector<std::size_t> lane_first(lane_count + 1, 0);
  std::vector<std::size_t> first_event;  // of each new region
  for (std::size_t l = 0; l < lane_count; ++l) {
    Lane& lane = *lanes_[l];
    lane_first[l + 1] = lane_first[l] + lane.regions.size();
    first_event.insert(first_event.end(), lane.first_event.begin(), lane.first_event.end());
    for (RegionRecord& region : lane.regions) regions.push_back(std::move(region));
  }
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
  tbb::parallel_for(all_events, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (region_of[i] == kNone) continue;
      const std::size_t lane = region_of[i] >> kLaneShift, local = region_of[i] & ((std::size_t{1} << kLaneShift) - 1);
      region_of[i] = new_index[lane_first[lane] + local];
    }
  });
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
    grow(survivor.bounds, merged.bounds);
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
    grow(track.bounds, region.bounds);
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
