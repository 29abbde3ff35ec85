#include "exporters/frame_positions.hpp"

#include "libcd/core/error.hpp"

namespace snag::exporters {

namespace {

[[noreturn]] void mismatch(const std::string& report_path, const std::string& problem) {
  throw InputError(InputLocation{report_path}, "the --cache inputs are not the cache of this report: " + problem);
}

}  // namespace

FramePositions::FramePositions(const ReportDigest& digest, io::CacheOptions options) : report_path_(digest.path) {
  if (options.inputs.empty()) throw UsageError("give the cache of " + digest.path + " with --cache");
  const report::Header& header = digest.header;
  options.frames = header.settings.frames.empty() ? io::FrameSelection{}
                                                  : io::parse_frame_selection(header.settings.frames);
  options.weld = io::parse_weld(header.settings.weld.empty() ? "auto" : header.settings.weld);
  source_ = io::open_cache(options);

  const std::vector<Object>& objects = source_->scene().objects();
  if (objects.size() != header.objects.size()) {
    mismatch(report_path_, "it has " + std::to_string(objects.size()) + " objects, the report " +
                               std::to_string(header.objects.size()));
  }
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const report::ObjectInfo& expected = header.objects[o];
    const Object& object = objects[o];
    if (object.name != expected.name) {
      mismatch(report_path_, "object " + std::to_string(o) + " is '" + object.name + "', the report's '" +
                                 expected.name + "' (order the inputs as the scan did, or name them with --name)");
    }
    if (object.vertex_count != expected.vertices || object.triangles.size() != expected.triangles) {
      mismatch(report_path_, "object '" + object.name + "' has " + std::to_string(object.vertex_count) +
                                 " vertices and " + std::to_string(object.triangles.size()) +
                                 " triangles, the report's " + std::to_string(expected.vertices) + " and " +
                                 std::to_string(expected.triangles));
    }
  }
  if (source_->frame_count() != header.frame_count) {
    mismatch(report_path_, "it has " + std::to_string(source_->frame_count()) + " frames (selection '" +
                               header.settings.frames + "'), the report " + std::to_string(header.frame_count));
  }
  for (std::size_t i = 0; i < source_->frame_count(); ++i) position_of_index_[source_->frame_index(i)] = i;
}

FramePositions::~FramePositions() = default;

const Scene& FramePositions::scene() const { return source_->scene(); }

bool FramePositions::has_frame(std::size_t frame) const { return position_of_index_.count(frame) > 0; }

std::vector<Vec3> FramePositions::positions(std::size_t frame) const {
  auto found = position_of_index_.find(frame);
  if (found == position_of_index_.end()) {
    throw UsageError(report_path_ + ": frame " + std::to_string(frame) + " was not scanned");
  }
  std::vector<Vec3> positions;
  source_->read_frame(found->second, positions);
  return positions;
}

std::map<std::size_t, std::vector<Vec3>> FramePositions::positions(const std::set<std::size_t>& frames) const {
  std::map<std::size_t, std::vector<Vec3>> all;
  for (std::size_t frame : frames) all.emplace(frame, positions(frame));
  return all;
}

}  // namespace snag::exporters
