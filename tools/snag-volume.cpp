// snag-volume: how deep and how much, per intersection region of a report.
// Reads a report and its cache, measures each intersection region of the
// chosen frames (overlap volume of closed objects, penetration depth and area
// of an open object in a closed one, intersection-curve length of open
// objects), writes the report again with the measures in its regions, prints
// a table, and with --vdb writes the level sets and overlaps of each frame.
#include <openvdb/openvdb.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include "exporters/digest.hpp"
#include "exporters/frame_positions.hpp"
#include "libcd/core/error.hpp"
#include "report/report_reader.hpp"
#include "report/report_writer.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/replacing_file.hpp"
#include "tools/common/run_tool.hpp"
#include "volume/region_measure.hpp"
#include "volume/vdb_file.hpp"

namespace {

namespace rp = snag::report;
namespace vol = snag::volume;

struct VolumeOptions {
  std::string report, output, vdb_directory;
  std::string frames;  ///< --frames: the cache frames whose regions are measured
  double voxel_size = 0;
  bool quiet = false;
};

// One frame's meshes, read when a region of the frame needs them.
class FrameMeshes {
 public:
  explicit FrameMeshes(const snag::exporters::FramePositions& positions) : positions_(positions) {}

  const vol::TriangleMesh& mesh(std::size_t frame, std::size_t object) {
    if (frame != frame_) {
      frame_ = frame;
      frame_positions_ = positions_.positions(frame);
      meshes_.clear();
    }
    auto found = meshes_.find(object);
    if (found == meshes_.end()) {
      found = meshes_.emplace(object, vol::object_mesh(positions_.scene(), object, frame_positions_)).first;
    }
    return found->second;
  }

 private:
  const snag::exporters::FramePositions& positions_;
  std::size_t frame_ = static_cast<std::size_t>(-1);
  std::vector<snag::Vec3> frame_positions_;
  std::map<std::size_t, vol::TriangleMesh> meshes_;
};

std::string measure_text(const rp::RegionMeasures& m) {
  char text[160];
  if (m.measure == "overlap_volume" || m.measure == "self_overlap_volume") {
    std::snprintf(text, sizeof text, "volume %.6g (+-%.2g)", m.volume, m.volume_error);
  } else if (m.measure == "penetration") {
    std::snprintf(text, sizeof text, "depth %.6g (+-%.2g)  area %.6g (+-%.2g)", m.depth, m.depth_error, m.area,
                  m.area_error);
  } else {
    std::snprintf(text, sizeof text, "curve %.6g (%zu segments)", m.curve_length, m.segments);
  }
  return text;
}

int run(const VolumeOptions& options, const snag::tools::CacheArguments& cache) {
  openvdb::initialize();
  rp::ReportReader reader(options.report);
  snag::exporters::ReportDigest digest;  // FramePositions needs the path and the header only
  digest.path = options.report;
  digest.header = reader.header();
  const snag::exporters::FramePositions positions(digest, snag::tools::to_cache_options(cache));
  const std::vector<snag::Object>& objects = positions.scene().objects();

  std::optional<snag::io::FrameSelection> frames;
  if (!options.frames.empty()) frames = snag::io::parse_frame_selection(options.frames);
  auto chosen = [&](std::size_t frame) {
    return !frames || (frame >= frames->first && frame <= frames->last && (frame - frames->first) % frames->step == 0);
  };
  if (!options.vdb_directory.empty()) std::filesystem::create_directories(options.vdb_directory);

  std::vector<vol::ObjectShape> shapes;
  for (const snag::Object& object : objects) shapes.push_back(vol::object_shape(object));
  std::map<std::size_t, vol::VertexFaces> vertex_faces;  // of the open objects that need them
  FrameMeshes meshes(positions);

  std::unique_ptr<snag::tools::ReplacingFile> output;
  std::unique_ptr<rp::ReportWriter> writer;
  rp::Header header = reader.header();
  header.tool = "snag-volume";
  if (!options.output.empty()) {
    output = std::make_unique<snag::tools::ReplacingFile>(options.output);
    writer = std::make_unique<rp::ReportWriter>(output->stream());
    writer->write_header(header);
  }

  vol::FrameGrids grids;
  std::size_t grid_frame = 0, vdb_files = 0, measured = 0;
  auto write_grids = [&] {
    if (options.vdb_directory.empty() || grids.empty()) return;
    grids.write(vol::vdb_path(options.vdb_directory, snag::exporters::report_stem(options.report), grid_frame),
                grid_frame);
    grids.clear();
    ++vdb_files;
  };
  if (!options.quiet) {
    std::printf("%-6s %-6s %-24s %-20s %-10s %s\n", "region", "frame", "objects", "measure", "voxel", "value");
  }

  for (rp::ReportReader::Record record; (record = reader.next()) != rp::ReportReader::Record::kEnd;) {
    switch (record) {
      case rp::ReportReader::Record::kFrame:
        write_grids();
        if (writer) writer->write_frame(reader.frame());
        break;
      case rp::ReportReader::Record::kEvent:
        if (writer) writer->write_event(reader.event());
        break;
      case rp::ReportReader::Record::kRegion: {
        rp::RegionRecord region = reader.region();
        if (region.kind == snag::EventKind::kIntersection && chosen(region.frame)) {
          const bool self = region.object_a == region.object_b;
          auto side = [&](std::size_t object, const std::vector<std::size_t>& faces) {
            vol::RegionSide s;
            s.mesh = &meshes.mesh(region.frame, object);
            s.shape = shapes[object];
            s.faces = faces.empty() ? vol::faces_near(*s.mesh, {region.bounds.lo, region.bounds.hi}) : faces;
            if (!s.shape.closed()) {
              auto found = vertex_faces.find(object);
              if (found == vertex_faces.end()) {
                found = vertex_faces.emplace(object, vol::vertex_faces(s.mesh->triangles, s.mesh->vertices.size())).first;
              }
              s.vertex_faces = &found->second;
            }
            return s;
          };
          const vol::RegionSide a = side(region.object_a, region.faces_a);
          const vol::RegionSide b = self ? a : side(region.object_b, region.faces_b);
          vol::MeasuredRegion result = vol::measure_region(region, a, b, options.voxel_size);
          region.measures = result.measures;
          grid_frame = region.frame;
          for (const vol::NamedGrid& grid : result.grids) grids.add(grid);
          ++measured;
          if (!options.quiet) {
            const std::string pair = snag::exporters::pair_label(header, region.object_a, region.object_b);
            std::printf("%-6zu %-6zu %-24s %-20s %-10.4g %s\n", region.id, region.frame, pair.c_str(),
                        result.measures.measure.c_str(), result.measures.voxel_size,
                        measure_text(result.measures).c_str());
          }
        }
        if (writer) writer->write_region(region);
        break;
      }
      case rp::ReportReader::Record::kTrack:
        if (writer) writer->write_track(reader.track());
        break;
      case rp::ReportReader::Record::kTrailer:
        if (writer) writer->write_trailer(reader.trailer());
        break;
      case rp::ReportReader::Record::kEnd:
        break;
    }
  }
  write_grids();
  if (writer) {
    writer->flush();
    output->commit();
  }
  if (!options.quiet) {
    std::printf("%zu regions measured", measured);
    if (!options.vdb_directory.empty()) std::printf(", %zu .vdb files in %s", vdb_files, options.vdb_directory.c_str());
    std::printf("\n");
  }
  return snag::tools::kExitClean;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-volume: how deep and how much, per intersection region of a report: overlap volumes of\n"
               "closed objects, penetration depth and area of cloth in a body, intersection-curve length of\n"
               "open objects; the report again with the measures, and .vdb grids.\n"
               "  snag-volume REPORT CACHE... [-t MESH]... [--frames A:B] [--voxel-size S] [--vdb DIR] [-o FILE]"};
  VolumeOptions options;
  snag::tools::CacheArguments cache;
  app.add_option("report", options.report, "The scan report (JSON Lines, snag-report(5))")->required()->type_name("REPORT");
  // The cache inputs and their options as every tool takes them; --frames
  // picks the frames to measure (the cache is read with the report's selection).
  snag::tools::add_cache_options(app, cache);
  app.get_option("--frames")->description("Measure the regions of these cache frames only: A:B, A:B:STEP, A: or A (default: all)");
  app.remove_option(app.get_option("--weld"));  // the report's weld applies
  app.add_option("--voxel-size", options.voxel_size,
                 "Voxel size in scene units (default: per region, half the mean edge length of its faces and at\n"
                 "most a sixteenth of its box)")
      ->check(CLI::PositiveNumber)
      ->type_name("S");
  app.add_option("--vdb", options.vdb_directory,
                 "Write one .vdb per frame with regions into DIR (STEM_NNNN.vdb): each object's level set near its\n"
                 "regions and each region's overlap, in world units")
      ->type_name("DIR");
  app.add_option("-o,--output", options.output, "Write the report with each measured region's measures to FILE")
      ->type_name("FILE");
  app.add_flag("-q,--quiet", options.quiet, "Print nothing but errors");
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;

  return snag::tools::run_tool("snag-volume", [&] {
    options.frames = cache.frames;
    cache.frames.clear();
    return run(options, cache);
  });
}
