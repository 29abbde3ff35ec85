// snag-info: what is in a cache — objects, frames, counts, bounds, triangle
// sizes, degenerate and non-manifold elements, and what the virtual
// subdivision scheme would do with it.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "libcd/stats/cache_statistics.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/run_tool.hpp"

namespace {

using snag::CacheStatistics;
using snag::tools::CacheArguments;

nlohmann::json to_json(const CacheStatistics& s, const snag::FrameSource& source) {
  nlohmann::json objects = nlohmann::json::array();
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const auto& o = s.objects[i];
    const snag::Object& object = source.scene().objects()[i];
    objects.push_back({{"name", o.name},
                       {"vertices", o.vertices},
                       {"file_vertices", snag::file_vertex_count(object)},
                       {"weld", object.weld.method},
                       {"triangles", o.triangles},
                       {"edges", o.edges},
                       {"boundary_edges", o.boundary_edges},
                       {"non_manifold_edges", o.non_manifold_edges},
                       {"degenerate_triangles", o.degenerate_triangles}});
  }
  auto range = [](const snag::Range& r) { return nlohmann::json{{"min", r.min}, {"mean", r.mean}, {"max", r.max}}; };
  auto vec = [](const snag::Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  return {{"version", 1},
          {"source", source.description()},
          {"objects", objects},
          {"frames", s.frames},
          {"time_range", {s.first_time, s.last_time}},
          {"bounds", {{"min", vec(s.bounds_min)}, {"max", vec(s.bounds_max)}}},
          {"triangle_sphere_radius", range(s.sphere_radius)},
          {"virtual_subdivision",
           {{"lambda", s.lambda},
            {"cell_size", range(s.cell_size)},
            {"subdivided_triangles", s.subdivided_triangles},
            {"levels", s.subdivision_levels}}},
          {"max_displacement",
           {{"over_cell_size", s.max_displacement_over_cell},
            {"frame", s.max_displacement_frame},
            {"vertex", s.max_displacement_vertex}}}};
}

void print_human(const CacheStatistics& s, const snag::FrameSource& source) {
  std::printf("source      %s\n", source.description().c_str());
  std::printf("objects     %zu\n", s.objects.size());
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const auto& o = s.objects[i];
    const snag::Object& object = source.scene().objects()[i];
    std::printf("  %-20s %9zu vertices %9zu triangles %9zu edges\n", o.name.c_str(), o.vertices, o.triangles,
                o.edges);
    std::printf("  %-20s %9zu boundary edges, %zu non-manifold edges, %zu degenerate triangles\n", "",
                o.boundary_edges, o.non_manifold_edges, o.degenerate_triangles);
    if (object.weld.method != "none") {
      const std::size_t file_vertices = snag::file_vertex_count(object);
      std::printf("  %-20s welded %zu file vertices into %zu (%s)\n", "", file_vertices, o.vertices,
                  object.weld.method.c_str());
    }
  }
  std::printf("frames      %zu (time %g to %g)\n", s.frames, s.first_time, s.last_time);
  if (s.frames == 0) return;
  std::printf("bounds      (%g, %g, %g) to (%g, %g, %g)\n", s.bounds_min.x, s.bounds_min.y, s.bounds_min.z,
              s.bounds_max.x, s.bounds_max.y, s.bounds_max.z);
  std::printf("triangle bounding-sphere radius  min %.6g  mean %.6g  max %.6g\n", s.sphere_radius.min,
              s.sphere_radius.mean, s.sphere_radius.max);
  std::printf("cell size (3 x %.2g x mean radius)  %.6g", s.lambda, s.cell_size.mean);
  if (s.cell_size.max > s.cell_size.min) {
    std::printf(" (from %.6g to %.6g over the frames)", s.cell_size.min, s.cell_size.max);
  }
  std::printf("\nvirtual subdivision  %zu triangles subdivided, up to %d level%s\n", s.subdivided_triangles,
              s.subdivision_levels, s.subdivision_levels == 1 ? "" : "s");
  if (s.frames > 1) {
    std::printf("largest displacement  %.4g cell sizes (vertex %zu, frame %zu to %zu)\n", s.max_displacement_over_cell,
                s.max_displacement_vertex, s.max_displacement_frame, s.max_displacement_frame + 1);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-info: summarise an animated mesh cache"};
  CacheArguments cache;
  bool json = false;
  double lambda = snag::kDefaultLambda;
  snag::tools::add_cache_options(app, cache);
  app.add_flag("--json", json, "Write JSON to standard output instead of the human summary");
  app.add_option("--lambda", lambda, "Cell-size coefficient of the virtual subdivision scheme (> 1)")
      ->check(CLI::Range(1.0, 100.0));
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;

  return snag::tools::run_tool("snag-info", [&] {
    auto source = snag::io::open_cache(snag::tools::to_cache_options(cache));
    CacheStatistics stats = snag::compute_cache_statistics(*source, lambda);
    if (json) {
      std::cout << to_json(stats, *source).dump(2) << "\n";
    } else {
      print_human(stats, *source);
    }
    return snag::tools::kExitClean;
  });
}
