// Regions and tracks: what a person acts on instead of a flood of pairs.
//
// A region is a connected set of faces of one frame (intersections) or one
// step (collisions) between one pair of objects: the faces of the events of
// that pair and kind, joined when an event names both (two faces that
// intersect; the faces of the elements of one collision) or when they share
// a vertex. The faces of a collision's elements are the face of a
// vertex–face pair with the faces around its vertex, and the faces on each
// edge of an edge–edge pair.
//
// A track joins the regions of consecutive frames (positions in the scan)
// that share a face, for the same pair of objects and kind. When a region
// joins several tracks, the one with the smallest id goes on, takes in the
// others' counts and frames, and the others end with `merged_into` set.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include "libcd/pipeline/event.hpp"
#include "libcd/scene/scene.hpp"
#include "report/concurrent_union_find.hpp"
#include "report/records.hpp"

namespace snag::report {

/// The objects of an event's two elements, smaller index first.
std::pair<std::size_t, std::size_t> event_objects(const Scene& scene, const Event& event);

/// An event's group, its kind and pair of objects, in one word that orders
/// groups as (kind, object a, object b) do: the kind in the top bit, object
/// a <= b in the next 31 and b in the low 32. kNoGroup: an event in no region.
using GroupWord = std::uint64_t;
constexpr GroupWord kNoGroup = ~GroupWord{0};
inline GroupWord group_word(EventKind kind, std::size_t a, std::size_t b) {
  return (GroupWord{kind == EventKind::kIntersection} << 63) | (GroupWord{a} << 32) | GroupWord{b};
}

/// The faces around each vertex and on each edge of a scene (the latter in
/// the order of the faces around the edge's first end), in compressed rows:
/// what a region builder reads of the mesh, the same for every builder of
/// the scene.
struct FaceAdjacency {
  explicit FaceAdjacency(const Scene& scene);
  std::vector<Index> vertex_face_start, vertex_faces;
  std::vector<Index> edge_face_start, edge_faces;
};

/// Builds the regions of one frame. Holds scene-sized scratch arrays so that
/// each frame costs time in the number of its events, not of the scene,
/// but for reading the marks (a bit per face, vertex and edge) of the two
/// objects of each group.
///
/// The events are grouped by pair and kind on all threads (in blocks, whose
/// runs of one group then take their places in event order). Two groups are
/// built at once, each on a lane with scratch of its own. Each group's
/// events are read once, on all threads: their elements marked and the two
/// sets each joins kept, in a union-find over faces and vertices (whose roots
/// are the smallest face of each region, so that the regions do not depend
/// on the threads). The faces around the marked vertices and on the marked
/// edges are marked in turn, the marked faces listed and joined with their
/// vertices, and then each event's sets joined (by then, most events find
/// both in one set and write nothing). The regions are numbered in the order
/// of their first events, found on all threads. Then, at once: each region's
/// positions added up in event order, on one thread; counts, boxes and times,
/// exact in any order, on all threads; each face's region found on all
/// threads and each region's faces listed in face order on one thread. The
/// result is the same for any number of threads.
class RegionBuilder {
 public:
  /// `faces`: the scene's adjacency, when several builders share it (made
  /// here when null).
  explicit RegionBuilder(const Scene& scene, std::shared_ptr<const FaceAdjacency> faces = nullptr);

  /// Groups events[i] with in_region[i] set (the checked ones) into regions
  /// of frame `frame`, appended to `regions` in the order of their first
  /// event (ids and tracks left 0 for the caller). region_of[i] is the index
  /// in `regions` of event i's region, or kNone. x: the frame's positions.
  void build(const std::vector<Event>& events, const std::vector<char>& in_region, const std::vector<Vec3>& x,
             std::size_t frame, std::vector<RegionRecord>& regions, std::vector<std::size_t>& region_of);
  /// As above, with each event's group word given (kNoGroup: in no region),
  /// so that the events are not read again to group them.
  void build(const std::vector<Event>& events, const std::vector<GroupWord>& group_of, const std::vector<Vec3>& x,
             std::size_t frame, std::vector<RegionRecord>& regions, std::vector<std::size_t>& region_of);

 private:
  using GroupKey = std::tuple<int, std::size_t, std::size_t>;  // kind, object a <= object b

  struct Lane;
  /// Lists the faces of the group's events in lane.touched (ascending) and
  /// joins those that an event names together or that share a vertex; keeps
  /// the two sets and the place of each event.
  void join_faces(Lane& lane, const std::vector<Event>& events, const std::vector<std::size_t>& group,
                  std::size_t object_a, std::size_t object_b) const;
  /// Lists in groups_ the events of each group (pair and kind), in event order.
  void group_events(const std::vector<GroupWord>& group_of);
  /// Adds the group's regions to lane.regions in the order of their first
  /// event and sets region_of for its events (the lane's index of their
  /// region, tagged with the lane), after join_faces on the group.
  void add_regions(Lane& lane, const std::vector<std::size_t>& group, const GroupKey& key, const std::vector<Vec3>& x,
                   std::size_t frame, std::vector<std::size_t>& region_of) const;

  const Scene& scene_;
  std::shared_ptr<const FaceAdjacency> faces_;
  /// The union-find's set of vertex v (after the faces').
  Index vertex_set(Index v) const { return static_cast<Index>(scene_.triangle_count()) + v; }

  struct RegionSums {  // a region's count, box and earliest time over a block of its events
    std::size_t events;
    Bounds bounds;
    double toi;
  };
  // Groups built at once, at most; a lane's regions are named in region_of,
  // until the frame's are ordered, by the lane above kLaneShift.
  static constexpr std::size_t kLanes = 2;
  static constexpr unsigned kLaneShift = 48;
  /// What one group is built in. Scratch, scene-sized, left as it was found
  /// after each group: no face, vertex or edge marked, no root with a region
  /// (the union-find is cleared before each group).
  struct Lane {
    Lane(const Scene& scene, std::size_t index);
    std::unique_ptr<std::atomic<std::uint64_t>[]> face_marks;    // a bit per face: the group's faces
    std::unique_ptr<std::atomic<std::uint64_t>[]> vertex_marks;  // a bit per vertex: the events' vertices
    std::unique_ptr<std::atomic<std::uint64_t>[]> edge_marks;    // a bit per edge: the events' edges
    ConcurrentUnionFind<Index> face_sets;                        // faces, then vertices
    // By face, kNone but at the group's roots: the first event of the root's
    // set while the roots are found, then its region.
    std::unique_ptr<std::atomic<std::size_t>[]> region_of_root;
    std::vector<std::vector<Index>> block_roots;  // by block of the group's events: the roots it found first
    std::vector<std::size_t> marked_before;                      // faces marked in the words before each block
    std::vector<Index> touched;                                  // the group's faces, ascending
    std::vector<std::size_t> touched_region;                     // the region of each of the group's faces
    std::vector<Bounds> touched_box;                             // intersections: the box of each of the group's faces
    std::vector<Index> event_first_set, event_second_set;        // the sets each of the group's events joins
    std::vector<Vec3> event_position;                            // of each of the group's events
    std::vector<double> event_toi;                               // collisions: frame + toi_lo of each
    std::vector<Index> event_root;                               // the root of each of the group's events
    std::vector<Index> group_roots;                              // the roots of the group's regions
    std::vector<RegionSums> block_sums;                          // by block of the group's events, then region
    // The frame's regions built on this lane so far, and the first event of each.
    std::vector<RegionRecord> regions;
    std::vector<std::size_t> first_event;
    std::size_t tag;  // the lane in region_of
  };
  std::map<GroupKey, std::vector<std::size_t>> groups_;  // the frame's events of each group
  std::vector<GroupWord> group_of_;                      // build() from in_region: each event's group
  std::vector<std::unique_ptr<Lane>> lanes_;             // made when a frame first needs them
};

/// Gives regions their track ids frame after frame and says when tracks end.
class TrackBuilder {
 public:
  explicit TrackBuilder(const Scene& scene);

  /// The regions of the frame at scan position `position` (cache index
  /// `frame`), ids set; sets each region's track. Tracks that ended (no
  /// region of this frame went on with them, or merged here) are appended to
  /// `ended`, in id order.
  void add_frame(std::size_t position, std::size_t frame, std::vector<RegionRecord>& regions,
                 std::vector<TrackRecord>& ended);
  /// Ends every open track (appended in id order).
  void finish(std::vector<TrackRecord>& ended);
  std::size_t tracks_started() const { return next_id_; }

 private:
  using FaceKey = std::uint64_t;  // pair and kind above, global face below
  FaceKey key(const RegionRecord& r, std::size_t object, std::size_t local_face) const;
  /// Appends the tracks of the last frame that hold one of `faces` (local,
  /// ascending) of `object`, for the region's pair and kind.
  void tracks_touched(const RegionRecord& region, std::size_t object, const std::vector<std::size_t>& faces,
                      std::vector<std::size_t>& tracks) const;

  const Scene& scene_;
  std::size_t next_id_ = 0;
  std::size_t last_position_ = kNone;
  std::map<std::size_t, TrackRecord> open_;                 // by id: tracks with a region in the last frame
  std::vector<std::pair<FaceKey, std::size_t>> last_faces_;  // sorted: the last frame's faces and their tracks
};

}  // namespace snag::report
