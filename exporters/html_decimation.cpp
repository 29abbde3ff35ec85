#include "exporters/html_decimation.hpp"

#include <algorithm>
#include <cmath>

namespace snag::exporters {
namespace {

using Flags = std::vector<std::vector<char>>;  // per object, per face

std::size_t base64_size(std::size_t bytes) { return (bytes + 2) / 3 * 4; }

Flags empty_flags(const HtmlScene& scene) {
  Flags flags(scene.objects.size());
  for (std::size_t o = 0; o < scene.objects.size(); ++o) flags[o].assign(scene.objects[o].triangles.size(), 0);
  return flags;
}

std::vector<std::vector<std::uint32_t>> faces_of(const Flags& flags) {
  std::vector<std::vector<std::uint32_t>> faces(flags.size());
  for (std::size_t o = 0; o < flags.size(); ++o)
    for (std::size_t f = 0; f < flags[o].size(); ++f)
      if (flags[o][f]) faces[o].push_back(static_cast<std::uint32_t>(f));
  return faces;
}

/// Faces of frame `slot` with a corner inside a region's bounds of that
/// frame, grown by the margin.
Flags near_faces(const HtmlScene& scene, const std::vector<ViewRegion>& regions, std::size_t slot) {
  Flags near = empty_flags(scene);
  const HtmlFrame& frame = scene.frames[slot];
  // The frame's bounding box, for the smallest margin.
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& positions : frame.objects)
    for (std::size_t i = 0; i + 2 < positions.size(); i += 3)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], double(positions[i + k]));
        hi[k] = std::max(hi[k], double(positions[i + k]));
      }
  double frame_diagonal = 0;
  for (int k = 0; k < 3; ++k) frame_diagonal += hi[k] > lo[k] ? (hi[k] - lo[k]) * (hi[k] - lo[k]) : 0;
  frame_diagonal = std::sqrt(frame_diagonal);

  std::vector<std::array<double, 6>> boxes;
  for (const ViewRegion& region : regions) {
    if (region.frame_slot != slot) continue;
    const Vec3 size = region.bounds.hi - region.bounds.lo;
    const double margin = std::max(0.5 * std::sqrt(squared_norm(size)), 0.05 * frame_diagonal);
    boxes.push_back({region.bounds.lo.x - margin, region.bounds.lo.y - margin, region.bounds.lo.z - margin,
                     region.bounds.hi.x + margin, region.bounds.hi.y + margin, region.bounds.hi.z + margin});
  }
  if (boxes.empty()) return near;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const std::vector<float>& positions = frame.objects[o];
    std::vector<char> vertex_near(positions.size() / 3, 0);
    for (std::size_t v = 0; v < vertex_near.size(); ++v) {
      const double p[3] = {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
      for (const auto& b : boxes)
        if (p[0] >= b[0] && p[1] >= b[1] && p[2] >= b[2] && p[0] <= b[3] && p[1] <= b[4] && p[2] <= b[5]) {
          vertex_near[v] = 1;
          break;
        }
    }
    const auto& triangles = scene.objects[o].triangles;
    for (std::size_t f = 0; f < triangles.size(); ++f)
      near[o][f] = vertex_near[triangles[f][0]] || vertex_near[triangles[f][1]] || vertex_near[triangles[f][2]];
  }
  return near;
}

void add_region_faces(Flags& flags, const std::vector<ViewRegion>& regions, std::size_t frames) {
  for (const ViewRegion& region : regions) {
    if (region.frame_slot >= frames) continue;
    for (std::size_t o = 0; o < region.faces.size() && o < flags.size(); ++o)
      for (std::size_t f : region.faces[o])
        if (f < flags[o].size()) flags[o][f] = 1;
  }
}

/// `keep` plus every `stride`-th face of `candidates` (stride 0: none).
Flags with_sample(const Flags& keep, const Flags& candidates, std::size_t stride) {
  Flags flags = keep;
  if (stride == 0) return flags;
  for (std::size_t o = 0; o < flags.size(); ++o) {
    std::size_t seen = 0;
    for (std::size_t f = 0; f < flags[o].size(); ++f)
      if (candidates[o][f] && !keep[o][f] && seen++ % stride == 0) flags[o][f] = 1;
  }
  return flags;
}

std::size_t face_count(const Flags& flags) {
  std::size_t n = 0;
  for (const auto& object : flags) n += static_cast<std::size_t>(std::count(object.begin(), object.end(), 1));
  return n;
}

/// The densest sample of `candidates` besides `keep` that fits, doubling the
/// stride from 1; `keep` alone when nothing fits (fits = false then when
/// `keep` alone is over too).
Flags fit_sample(const HtmlScene& scene, const Flags& keep, const Flags& candidates, std::size_t frames,
                 std::size_t budget, bool& fits) {
  const std::size_t most = face_count(candidates) + 1;
  for (std::size_t stride = 1; stride <= most; stride *= 2) {
    Flags flags = with_sample(keep, candidates, stride);
    if (view_bytes(scene, faces_of(flags), frames) <= budget) {
      fits = true;
      return flags;
    }
  }
  fits = view_bytes(scene, faces_of(keep), frames) <= budget;
  return keep;
}

}  // namespace

std::size_t view_bytes(const HtmlScene& scene, const std::vector<std::vector<std::uint32_t>>& faces,
                       std::size_t frames) {
  std::size_t bytes = 0;
  for (std::size_t o = 0; o < scene.objects.size() && o < faces.size(); ++o) {
    std::vector<char> used(frames > 0 && !scene.frames.empty() ? scene.frames[0].objects[o].size() / 3 : 0, 0);
    for (std::uint32_t f : faces[o])
      for (std::uint32_t v : scene.objects[o].triangles[f])
        if (v < used.size()) used[v] = 1;
    const auto vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
    bytes += base64_size(12 * faces[o].size()) + frames * base64_size(12 * vertices);
  }
  return bytes;
}

ViewSelection select_view(const HtmlScene& scene, const std::vector<ViewRegion>& regions, std::size_t budget) {
  ViewSelection selection;
  if (scene.frames.empty()) {
    selection.faces.resize(scene.objects.size());
    return selection;
  }
  Flags all = empty_flags(scene);
  for (auto& object : all) std::fill(object.begin(), object.end(), 1);

  std::vector<Flags> near_by_frame;
  for (std::size_t slot = 0; slot < scene.frames.size(); ++slot) near_by_frame.push_back(near_faces(scene, regions, slot));

  for (std::size_t frames = scene.frames.size(); frames >= 1; --frames) {
    if (view_bytes(scene, faces_of(all), frames) <= budget) {
      selection.frames = frames;
      selection.faces = faces_of(all);
      selection.decimated = false;
      return selection;
    }
    Flags near = empty_flags(scene);
    for (std::size_t slot = 0; slot < frames; ++slot)
      for (std::size_t o = 0; o < near.size(); ++o)
        for (std::size_t f = 0; f < near[o].size(); ++f) near[o][f] |= near_by_frame[slot][o][f];
    add_region_faces(near, regions, frames);
    bool fits = false;
    Flags chosen = fit_sample(scene, near, all, frames, budget, fits);
    if (fits || frames == 1) {
      if (!fits) {  // one frame, and its near faces alone are over: sample them too
        Flags regions_only = empty_flags(scene);
        add_region_faces(regions_only, regions, 1);
        chosen = fit_sample(scene, regions_only, near, 1, budget, fits);
      }
      selection.frames = frames;
      selection.faces = faces_of(chosen);
      selection.decimated = face_count(chosen) < face_count(all);
      return selection;
    }
  }
  return selection;  // not reached: the loop returns at frames == 1
}

}  // namespace snag::exporters
