// The regions of one frame built the plain way, from their definition in
// report/regions.hpp read literally: an event's faces found by scanning
// every triangle, one serial union-find in a std::map per pair and kind, and
// faces joined when they share a vertex. The oracle of RegionBuilder's tests.
#pragma once

#include <algorithm>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "report/regions.hpp"

namespace snag::test {

/// A region of the reference, with the events that made it (in event order).
inline void reference_regions(const Scene& scene, const std::vector<Event>& events, const std::vector<char>& in_region,
                              const std::vector<Vec3>& x, std::size_t frame,
                              std::vector<report::RegionRecord>& regions, std::vector<std::size_t>& region_of) {
  const auto& triangles = scene.triangles();
  auto has = [](const Triangle& t, Index v) { return t[0] == v || t[1] == v || t[2] == v; };
  auto faces_of = [&](const Event& e) {
    std::vector<Index> faces;
    auto on_edge = [&](Index id) {
      const Edge& edge = scene.edges()[id];
      for (Index f = 0; f < triangles.size(); ++f)
        if (has(triangles[f], edge[0]) && has(triangles[f], edge[1])) faces.push_back(f);
    };
    if (e.kind == EventKind::kIntersection) {
      faces = {e.a, e.b};
    } else if (e.type == ContactType::kVertexFace) {
      faces.push_back(e.b);
      for (Index f = 0; f < triangles.size(); ++f)
        if (has(triangles[f], e.a)) faces.push_back(f);
    } else {
      on_edge(e.a);
      on_edge(e.b);
    }
    return faces;
  };

  std::map<std::tuple<int, std::size_t, std::size_t>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (!in_region[i]) continue;
    const auto [a, b] = report::event_objects(scene, events[i]);
    groups[{static_cast<int>(events[i].kind), a, b}].push_back(i);
  }
  struct Built {
    std::size_t first_event;
    report::RegionRecord region;
  };
  std::vector<Built> built;
  std::vector<std::size_t> built_of(events.size(), report::kNone);
  for (const auto& [key, group] : groups) {
    std::map<Index, Index> parent;
    auto find = [&](Index f) {
      while (parent.at(f) != f) f = parent.at(f);
      return f;
    };
    auto unite = [&](Index a, Index b) { parent[find(a)] = find(b); };
    std::vector<std::vector<Index>> event_faces;
    for (std::size_t i : group) {
      event_faces.push_back(faces_of(events[i]));
      for (Index f : event_faces.back()) parent.emplace(f, f);
    }
    for (const auto& faces : event_faces)
      for (Index f : faces) unite(faces.front(), f);
    std::map<Index, Index> face_at_vertex;
    for (const auto& [f, p] : parent)
      for (Index v : triangles[f]) {
        const auto [it, first] = face_at_vertex.emplace(v, f);
        if (!first) unite(it->second, f);
      }
    std::map<Index, std::size_t> built_of_root;
    for (std::size_t k = 0; k < group.size(); ++k) {
      const std::size_t i = group[k];
      const Event& e = events[i];
      const Index root = find(event_faces[k].front());
      auto [it, fresh] = built_of_root.emplace(root, built.size());
      if (fresh) {
        Built b{i, {}};
        b.region.kind = e.kind;
        b.region.object_a = std::get<1>(key);
        b.region.object_b = std::get<2>(key);
        b.region.frame = frame;
        const double inf = std::numeric_limits<double>::infinity();
        b.region.bounds = {{inf, inf, inf}, {-inf, -inf, -inf}};
        b.region.toi = inf;
        built.push_back(b);
      }
      report::RegionRecord& r = built[it->second].region;
      built_of[i] = it->second;
      ++r.events;
      r.centroid = r.centroid + e.position;
      if (e.kind == EventKind::kCollision) {
        r.bounds.lo = {std::min(r.bounds.lo.x, e.position.x), std::min(r.bounds.lo.y, e.position.y),
                       std::min(r.bounds.lo.z, e.position.z)};
        r.bounds.hi = {std::max(r.bounds.hi.x, e.position.x), std::max(r.bounds.hi.y, e.position.y),
                       std::max(r.bounds.hi.z, e.position.z)};
        r.toi = std::min(r.toi, static_cast<double>(e.frame) + e.toi_lo);
      }
    }
    for (const auto& [f, p] : parent) {  // ascending faces
      report::RegionRecord& r = built[built_of_root.at(find(f))].region;
      const std::size_t object = scene.object_of_triangle(f);
      (object == r.object_a ? r.faces_a : r.faces_b).push_back(f - scene.triangle_offset(object));
      if (r.kind == EventKind::kIntersection) {
        for (Index v : triangles[f]) {
          r.bounds.lo = {std::min(r.bounds.lo.x, x[v].x), std::min(r.bounds.lo.y, x[v].y), std::min(r.bounds.lo.z, x[v].z)};
          r.bounds.hi = {std::max(r.bounds.hi.x, x[v].x), std::max(r.bounds.hi.y, x[v].y), std::max(r.bounds.hi.z, x[v].z)};
        }
      }
    }
  }
  // The frame's regions in the order of their first event.
  std::vector<std::size_t> order(built.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t p, std::size_t q) { return built[p].first_event < built[q].first_event; });
  std::vector<std::size_t> place(built.size());
  const std::size_t first = regions.size();
  for (std::size_t k = 0; k < order.size(); ++k) {
    place[order[k]] = first + k;
    report::RegionRecord r = built[order[k]].region;
    r.face_count = r.faces_a.size() + r.faces_b.size();
    r.centroid = (1.0 / static_cast<double>(r.events)) * r.centroid;
    regions.push_back(r);
  }
  region_of.assign(events.size(), report::kNone);
  for (std::size_t i = 0; i < events.size(); ++i)
    if (built_of[i] != report::kNone) region_of[i] = place[built_of[i]];
}

/// Every field RegionBuilder sets, compared exactly; the first difference, or "".
inline std::string region_difference(const report::RegionRecord& p, const report::RegionRecord& q) {
  auto same = [](const Vec3& u, const Vec3& v) { return u.x == v.x && u.y == v.y && u.z == v.z; };
  if (p.kind != q.kind || p.object_a != q.object_a || p.object_b != q.object_b) return "pair or kind";
  if (p.frame != q.frame) return "frame";
  if (p.events != q.events) return "events";
  if (p.faces_a != q.faces_a || p.faces_b != q.faces_b || p.face_count != q.face_count) return "faces";
  if (!same(p.centroid, q.centroid)) return "centroid";
  if (!same(p.bounds.lo, q.bounds.lo) || !same(p.bounds.hi, q.bounds.hi)) return "bounds";
  if (!(p.toi == q.toi)) return "toi";
  return "";
}

}  // namespace snag::test
