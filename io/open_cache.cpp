#include "io/open_cache.hpp"

#include <filesystem>
#include <system_error>

#include "io/composite_source.hpp"
#include "io/frame_files.hpp"
#include "io/mesh_file.hpp"
#include "io/mesh_sequence_source.hpp"
#include "io/point_cache_source.hpp"
#include "io/reader_support.hpp"
#include "io/selected_frames_source.hpp"
#include "libcd/core/error.hpp"
#include "snag/config.hpp"

#if SNAG_HAVE_ASSIMP
#include "io/assimp_reader.hpp"
#endif

namespace snag::io {

namespace {

std::string format_label(const std::vector<FrameFile>& files) {
  std::string extension = lower_extension(files.front().path);
  for (char& c : extension) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
  return extension;
}

std::unique_ptr<FrameSource> open_listed_frames(const InputSpec& input) {
  std::vector<FrameFile> files;
  std::error_code error;
  for (const std::string& path : input.frame_files) {
    if (!std::filesystem::exists(path, error)) throw InputError({path}, "no such file");
    files.push_back({path, static_cast<double>(files.size())});
  }
  std::string description = format_label(files) + " frames " + input.frame_files.front() + " ... " +
                            input.frame_files.back() + " (" + std::to_string(files.size()) + " frames)";
  return std::make_unique<MeshSequenceSource>(std::move(files), input.name, std::move(description));
}

std::unique_ptr<FrameSource> open_input(const InputSpec& input, const CacheOptions& options) {
  if (!input.frame_files.empty()) return open_listed_frames(input);
  const std::string extension = lower_extension(input.path);
  if (!input.topology.empty()) return std::make_unique<PointCacheSource>(input.path, input.topology, input.name);
  if (extension == "pc2" || extension == "mdd") {
    throw UsageError(input.path + ": a point cache needs a topology mesh (the mesh whose vertices it moves)");
  }
  std::error_code error;
  std::vector<FrameFile> files;
  std::string what;
  if (std::filesystem::is_directory(input.path, error)) {
    files = list_directory_files(input.path);
    what = "sequence in " + input.path;
  } else if (is_frame_pattern(input.path)) {
    files = list_pattern_files(input.path);
    what = "sequence " + input.path;
  } else if (is_glob(input.path) && !std::filesystem::exists(input.path, error)) {
    files = list_glob_files(input.path);
    what = "sequence " + input.path;
  } else {
#if SNAG_HAVE_ASSIMP
    if (is_animated_extension(extension)) return open_animated_file(input, options);
#else
    (void)options;
#endif
    if (!std::filesystem::exists(input.path, error)) throw InputError({input.path}, "no such file");
    files.push_back({input.path, 0});
    what = "file " + input.path;
  }
  std::string description = format_label(files) + " " + what + " (" + std::to_string(files.size()) + " frames)";
  return std::make_unique<MeshSequenceSource>(std::move(files), input.name, std::move(description));
}

// kAuto welds what arrives with vertices split per face corner or normal
// seam: the formats assimp reads. OBJ, PLY and STL keep the file's vertices
// (STL's reader already joins equal corners), as do point caches, whose
// vertices must match the cache's.
WeldSettings resolve_weld(const WeldSettings& weld, const InputSpec& input) {
  if (weld.method != WeldSettings::Method::kAuto) return weld;
  WeldSettings resolved;
  resolved.method = WeldSettings::Method::kNone;
#if SNAG_HAVE_ASSIMP
  const std::string& path = input.frame_files.empty() ? input.path : input.frame_files.front();
  if (input.topology.empty() && is_assimp_extension(lower_extension(path))) {
    resolved.method = WeldSettings::Method::kExact;
  }
#else
  (void)input;
#endif
  return resolved;
}

bool selects_everything(const FrameSelection& selection) {
  return selection.first == 0 && selection.last == static_cast<std::size_t>(-1) && selection.step == 1;
}

}  // namespace

std::unique_ptr<FrameSource> open_cache(const CacheOptions& options) {
  if (options.inputs.empty()) throw UsageError("no input cache given");
  std::vector<std::unique_ptr<FrameSource>> parts;
  std::vector<std::string> labels;
  for (const InputSpec& input : options.inputs) {
    std::unique_ptr<FrameSource> part = weld_vertices(open_input(input, options), resolve_weld(options.weld, input));
    if (!selects_everything(options.frames)) part = std::make_unique<SelectedFramesSource>(std::move(part), options.frames);
    parts.push_back(std::move(part));
    labels.push_back(input.path);
  }
  return std::make_unique<CompositeSource>(std::move(parts), std::move(labels));
}

}  // namespace snag::io
