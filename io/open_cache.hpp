// Opens any supported cache as one FrameSource: per-frame mesh sequences
// (OBJ, PLY, STL, and assimp's formats), a topology mesh plus a point cache
// (PC2, MDD), one animated file (glTF, FBX, Collada), or several of these at
// once as several named objects.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/vertex_weld.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag::io {

/// One input on the command line.
struct InputSpec {
  /// A file, a printf-style pattern ("cloth_%04d.obj"), a glob ("cloth_*.obj")
  /// or a directory of per-frame meshes; or a point cache (.pc2, .mdd) when
  /// `topology` is set; or one animated file (.gltf, .glb, .fbx, .dae).
  std::string path;
  /// Topology mesh for a point cache (OBJ, PLY, STL ...). Empty otherwise.
  std::string topology;
  /// Object name override; empty keeps the names the file gives (OBJ o/g
  /// groups, node names) or the file's stem.
  std::string name;
  /// When not empty: the frames of one mesh sequence, one file each, in this
  /// order (e.g. a two-frame step t0.ply, t1.ply); `path` is then ignored.
  std::vector<std::string> frame_files;
};

/// Which frames to use: first, last (inclusive) and step, as 0-based indices
/// into the cache's own frames. last = npos means "to the end".
struct FrameSelection {
  std::size_t first = 0;
  std::size_t last = static_cast<std::size_t>(-1);
  std::size_t step = 1;
};

/// Parses "A:B", "A:B:S", "A:" or "A" (0-based, inclusive). Throws UsageError.
FrameSelection parse_frame_selection(const std::string& text);

struct CacheOptions {
  std::vector<InputSpec> inputs;
  FrameSelection frames;
  /// Animated files only: samples per second (default: the file's own
  /// ticks-per-second if it is a whole frame rate, else 24).
  std::optional<double> sample_rate;
  /// Animated files only: time range in seconds to sample (default: the
  /// animation's whole duration).
  std::optional<double> start_time, end_time;
  /// Welding of coincident vertices, per input; kAuto welds exactly the
  /// formats that split vertices (assimp's: FBX, Collada, glTF ...). The weld
  /// looks at every frame of the input, before the frame selection.
  WeldSettings weld;
};

/// Opens the inputs as one source. Several inputs become several objects in
/// input order; they must have the same number of frames (after selection).
/// Throws InputError for bad files, UsageError for bad options.
std::unique_ptr<FrameSource> open_cache(const CacheOptions& options);

}  // namespace snag::io
