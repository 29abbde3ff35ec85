#include "io/vertex_weld.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {
namespace {

using Bits = std::array<std::uint64_t, 3>;

bool is_finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// The exact key of a position: its coordinates' bit patterns, -0 made +0.
Bits position_bits(const Vec3& p) {
  Bits bits;
  for (int k = 0; k < 3; ++k) {
    double c = p[k];
    if (c == 0) c = 0;
    std::memcpy(&bits[k], &c, sizeof c);
  }
  return bits;
}

struct KeyedVertex {
  Index group;  ///< vertices are only joined within a group
  Bits bits;
  Index v;  ///< global vertex id
};

/// Sets rep[v] of every run of equal (group, bits) to the run's smallest v and
/// returns the members of the runs of two or more.
std::vector<Index> join_equal(std::vector<KeyedVertex>& keyed, std::vector<Index>& rep) {
  std::sort(keyed.begin(), keyed.end(), [](const KeyedVertex& a, const KeyedVertex& b) {
    return std::tie(a.group, a.bits, a.v) < std::tie(b.group, b.bits, b.v);
  });
  std::vector<Index> joined;
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i + 1;
    while (j < keyed.size() && keyed[j].group == keyed[i].group && keyed[j].bits == keyed[i].bits) ++j;
    for (std::size_t k = i; k < j; ++k) {
      rep[keyed[k].v] = keyed[i].v;
      if (j - i >= 2) joined.push_back(keyed[k].v);
    }
    i = j;
  }
  return joined;
}

/// Global vertex ranges [first, last) of the objects to weld, with their object index.
struct WeldRange {
  Index object, first, last;
};

/// Exact welding: rep[v] is the smallest vertex whose position equals v's in every frame.
std::vector<Index> exact_representatives(const FrameSource& source, const std::vector<WeldRange>& ranges) {
  std::vector<Index> rep(source.scene().vertex_count());
  std::iota(rep.begin(), rep.end(), Index{0});
  std::vector<Vec3> x;
  source.read_frame(0, x);
  std::vector<KeyedVertex> keyed;
  for (const WeldRange& range : ranges) {
    for (Index v = range.first; v < range.last; ++v) {
      if (is_finite(x[v])) keyed.push_back({range.object, position_bits(x[v]), v});
    }
  }
  std::vector<Index> active = join_equal(keyed, rep);
  for (std::size_t f = 1; f < source.frame_count() && !active.empty(); ++f) {
    source.read_frame(f, x);
    keyed.clear();
    for (Index v : active) {
      if (is_finite(x[v])) {
        keyed.push_back({rep[v], position_bits(x[v]), v});
      } else {
        rep[v] = v;  // a non-finite position joins nothing
      }
    }
    active = join_equal(keyed, rep);
  }
  return rep;
}

double squared_distance(const Vec3& a, const Vec3& b) {
  const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

/// Pairs (u < v) of vertices of one range within `distance` of each other in
/// `x`, found through a grid of cells `distance` wide. Throws UsageError past
/// `limit` pairs.
std::vector<std::pair<Index, Index>> close_pairs(const std::vector<Vec3>& x, const std::vector<WeldRange>& ranges,
                                                 double distance, std::size_t limit) {
  using Cell = std::array<std::int64_t, 4>;  // object, then integer cell coordinates
  constexpr double kLargestCell = 9.0e15;      // cell coordinates stay exact int64 values
  const auto cell_of = [&](Index object, const Vec3& p) {
    Cell cell{object, 0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const double c = std::floor(p[k] / distance);
      cell[k + 1] = static_cast<std::int64_t>(std::clamp(c, -kLargestCell, kLargestCell));
    }
    return cell;
  };
  std::vector<std::pair<Cell, Index>> cells;
  for (const WeldRange& range : ranges) {
    for (Index v = range.first; v < range.last; ++v) {
      if (is_finite(x[v])) cells.push_back({cell_of(range.object, x[v]), v});
    }
  }
  std::sort(cells.begin(), cells.end());
  const double d2 = distance * distance;
  std::vector<std::pair<Index, Index>> pairs;
  for (const auto& [cell, v] : cells) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const Cell next{cell[0], cell[1] + dx, cell[2] + dy, cell[3] + dz};
          auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(next, Index{0}));
          for (; it != cells.end() && it->first == next; ++it) {
            const Index u = it->second;
            if (u <= v || squared_distance(x[u], x[v]) > d2) continue;
            pairs.push_back({v, u});
            if (pairs.size() > limit) {
              std::ostringstream text;
              text << "--weld " << distance << ": more than " << with_thousands(limit)
                   << " vertex pairs lie within that distance in the first frame; a weld distance "
                      "should be far smaller than the mesh's edges";
              throw UsageError(text.str());
            }
          }
        }
      }
    }
  }
  return pairs;
}

Index find_root(std::vector<Index>& parent, Index v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

/// Distance welding: rep[v] is the smallest vertex joined to v by a chain of
/// vertices each within `distance` of the next in every frame.
std::vector<Index> distance_representatives(const FrameSource& source, const std::vector<WeldRange>& ranges,
                                            double distance) {
  const std::size_t n = source.scene().vertex_count();
  std::vector<Vec3> x;
  source.read_frame(0, x);
  std::vector<std::pair<Index, Index>> pairs = close_pairs(x, ranges, distance, kMaxWeldPairsPerVertex * n);
  const double d2 = distance * distance;
  for (std::size_t f = 1; f < source.frame_count() && !pairs.empty(); ++f) {
    source.read_frame(f, x);
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                               [&](const auto& p) { return !(squared_distance(x[p.first], x[p.second]) <= d2); }),
                pairs.end());
  }
  std::vector<Index> rep(n);
  std::iota(rep.begin(), rep.end(), Index{0});
  for (const auto& [u, v] : pairs) {
    const Index a = find_root(rep, u), b = find_root(rep, v);
    if (a != b) rep[std::max(a, b)] = std::min(a, b);
  }
  for (Index v = 0; v < n; ++v) rep[v] = find_root(rep, v);
  return rep;
}

std::string method_name(const WeldSettings& settings) {
  if (settings.method == WeldSettings::Method::kExact) return "exact";
  std::ostringstream text;
  text << "distance " << settings.distance;
  return text.str();
}

/// A source whose objects' coincident vertices are welded.
class WeldedSource : public FrameSource {
 public:
  WeldedSource(std::unique_ptr<FrameSource> source, const WeldSettings& settings) : source_(std::move(source)) {
    const Scene& scene = source_->scene();
    std::vector<WeldRange> ranges;
    for (std::size_t o = 0; o < scene.objects().size(); ++o) {
      ranges.push_back({static_cast<Index>(o), scene.vertex_offset(o), scene.vertex_offset(o + 1)});
    }
    const std::vector<Index> rep = source_->frame_count() == 0 ? std::vector<Index>{}
                                   : settings.method == WeldSettings::Method::kExact
                                       ? exact_representatives(*source_, ranges)
                                       : distance_representatives(*source_, ranges, settings.distance);
    build_scene(rep, method_name(settings));
  }

  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return source_->frame_count(); }
  double frame_time(std::size_t i) const override { return source_->frame_time(i); }
  std::size_t frame_index(std::size_t i) const override { return source_->frame_index(i); }
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override {
    source_->read_frame(i, positions);
    if (source_vertex_.empty()) return;
    // source_vertex_ ascends with source_vertex_[k] >= k, so this never
    // overwrites a position still to be read.
    for (std::size_t k = 0; k < source_vertex_.size(); ++k) positions[k] = positions[source_vertex_[k]];
    positions.resize(source_vertex_.size());
  }
  std::string description() const override { return description_; }

 private:
  void build_scene(const std::vector<Index>& rep, const std::string& method) {
    const Scene& scene = source_->scene();
    std::vector<Object> objects;
    std::size_t joined = 0;
    for (std::size_t o = 0; o < scene.objects().size(); ++o) {
      const Object& file_object = scene.objects()[o];
      const Index base = scene.vertex_offset(o);
      VertexWeld weld;
      weld.method = method;
      weld.vertex_of_file.resize(file_object.vertex_count);
      for (Index v = 0; v < file_object.vertex_count; ++v) {
        const Index r = rep.empty() ? v : rep[base + v] - base;
        if (r == v) {
          weld.vertex_of_file[v] = static_cast<Index>(weld.file_ids.size());
          weld.file_ids.push_back(v);
        } else {
          weld.vertex_of_file[v] = weld.vertex_of_file[r];  // r < v was numbered already
        }
      }
      std::vector<Triangle> triangles = file_object.triangles;
      for (Triangle& t : triangles) {
        for (Index& corner : t) corner = weld.vertex_of_file[corner];
      }
      const auto count = static_cast<Index>(weld.file_ids.size());
      Object object = make_object(file_object.name, count, std::move(triangles));
      for (Index id : weld.file_ids) source_vertex_.push_back(base + id);
      joined += file_object.vertex_count - count;
      if (count == file_object.vertex_count) {
        weld.file_ids.clear();
        weld.vertex_of_file.clear();
      }
      object.weld = std::move(weld);
      objects.push_back(std::move(object));
    }
    if (joined == 0) source_vertex_.clear();
    scene_ = Scene(std::move(objects));
    description_ = source_->description();
    if (joined > 0) {
      description_ += ", " + with_thousands(joined) + " coincident vertices welded (" + method + ")";
    }
  }

  std::unique_ptr<FrameSource> source_;
  Scene scene_;
  std::vector<Index> source_vertex_;  ///< global welded id -> global id in source_; empty when nothing was joined
  std::string description_;
};

}  // namespace

WeldSettings parse_weld(const std::string& text) {
  WeldSettings settings;
  if (text == "auto") return settings;
  if (text == "none") {
    settings.method = WeldSettings::Method::kNone;
    return settings;
  }
  if (text == "exact") {
    settings.method = WeldSettings::Method::kExact;
    return settings;
  }
  char* end = nullptr;
  const double distance = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(distance) || distance < 0) {
    throw UsageError("--weld '" + text + "': expected auto, none, exact or a distance >= 0");
  }
  settings.method = distance == 0 ? WeldSettings::Method::kExact : WeldSettings::Method::kDistance;
  settings.distance = distance;
  return settings;
}

std::unique_ptr<FrameSource> weld_vertices(std::unique_ptr<FrameSource> source, const WeldSettings& settings) {
  assert(settings.method != WeldSettings::Method::kAuto);
  if (settings.method == WeldSettings::Method::kNone) return source;
  return std::make_unique<WeldedSource>(std::move(source), settings);
}

}  // namespace snag::io
