// Hand-made reports and scenes for the HTML page tests: a flat grid of
// triangles as one object, with regions at chosen faces.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "exporters/digest.hpp"
#include "exporters/html.hpp"

namespace snag::test {

/// An n by n grid of quads (2 n² triangles, (n + 1)² vertices) in the unit
/// square of the z = 0 plane, lifted by `lift` in z at every frame.
inline exporters::HtmlMesh grid_mesh(std::size_t n) {
  exporters::HtmlMesh mesh;
  const auto id = [n](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(i * (n + 1) + j); };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

inline exporters::HtmlFrame grid_frame(std::size_t n, std::size_t frame, float lift = 0) {
  exporters::HtmlFrame positions;
  positions.frame = frame;
  positions.objects.emplace_back();
  for (std::size_t i = 0; i <= n; ++i)
    for (std::size_t j = 0; j <= n; ++j)
      positions.objects[0].insert(positions.objects[0].end(),
                                  {float(i) / float(n), float(j) / float(n), lift * float(frame)});
  return positions;
}

/// The faces of the grid's quad (i, j).
inline std::vector<std::size_t> quad_faces(std::size_t n, std::size_t i, std::size_t j) {
  return {2 * (i * n + j), 2 * (i * n + j) + 1};
}

/// A report on one object "sheet" (the grid) over `frames` frames, with one
/// self-intersection region per frame at quad (i, j) of the grid, one track
/// through them, and a failing verdict.
inline exporters::ReportDigest grid_report(std::size_t n, std::size_t frames, std::size_t i, std::size_t j,
                                           const std::string& path = "grid.jsonl") {
  exporters::ReportDigest digest;
  digest.path = path;
  digest.header.source = "a hand-made grid";
  digest.header.objects.push_back({"sheet", (n + 1) * (n + 1), (n + 1) * (n + 1), 2 * n * n, 0, "none", 0});
  digest.header.frame_count = frames;
  for (std::size_t f = 0; f < frames; ++f) {
    report::FrameRecord frame;
    frame.position = f;
    frame.index = f;
    frame.time = double(f + 1);
    frame.intersections = 3;
    frame.regions = 1;
    digest.frames.push_back(frame);
    report::RegionRecord region;
    region.id = f;
    region.kind = EventKind::kIntersection;
    region.frame = f;
    region.faces_a = quad_faces(n, i, j);
    region.face_count = region.faces_a.size();
    region.events = 3;
    const double s = 1.0 / double(n);
    region.bounds = {{double(i) * s, double(j) * s, 0}, {double(i + 1) * s, double(j + 1) * s, 0}};
    region.centroid = 0.5 * (region.bounds.lo + region.bounds.hi);
    digest.regions.push_back(region);
  }
  report::TrackRecord track;
  track.kind = EventKind::kIntersection;
  track.first_frame = 0;
  track.last_frame = frames - 1;
  track.frames = track.regions = frames;
  track.events = 3 * frames;
  track.max_faces = 2;
  digest.tracks.push_back(track);
  digest.trailer.frames = frames;
  digest.trailer.events = digest.trailer.intersections = 3 * frames;
  digest.trailer.regions = frames;
  digest.trailer.tracks = 1;
  digest.trailer.pass = false;
  digest.trailer.failed.push_back({"events", 3 * frames, 1});
  return digest;
}

/// The grid's scene with `frames` frames of positions, worst (frame 0) first.
inline exporters::HtmlScene grid_scene(std::size_t n, std::size_t frames) {
  exporters::HtmlScene scene;
  scene.objects.push_back(grid_mesh(n));
  for (std::size_t f = 0; f < frames; ++f) scene.frames.push_back(grid_frame(n, f, 0.01f));
  return scene;
}

}  // namespace snag::test
