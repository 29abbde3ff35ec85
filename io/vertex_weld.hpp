// Welding of coincident vertices: file vertices that sit at the same place in
// every frame of a cache become one vertex for topology (edges, adjacency,
// the shared-feature rules, representative triangles), while reports keep
// naming vertices by the file's ids (Object::weld).
//
// Formats such as FBX and Collada arrive with one vertex per face corner, and
// glTF splits vertices along normal seams; a garment's panels are stitched at
// coincident seam vertices. Without welding, neighbouring faces share no
// vertex id, so every pair of neighbours is a "collision" at distance zero.
#pragma once

#include <memory>
#include <string>

#include "libcd/scene/frame_source.hpp"

namespace snag::io {

/// Which file vertices are joined.
struct WeldSettings {
  enum class Method {
    kAuto,      ///< kExact for formats that split vertices (assimp's), kNone for OBJ, PLY, STL, point caches
    kNone,      ///< every file vertex is its own vertex
    kExact,     ///< positions bit-identical in every frame (-0 and +0 are the same; non-finite never joins)
    kDistance,  ///< positions within `distance` of each other in every frame, joined transitively
  };
  Method method = Method::kAuto;
  double distance = 0;  ///< kDistance only: scene units, > 0
};

/// Parses "auto", "none", "exact" or a distance ("0.001"; "0" means exact).
/// Throws UsageError naming the value.
WeldSettings parse_weld(const std::string& text);

/// Most file vertex pairs within the distance of kDistance that one weld may
/// examine, per vertex of the cache: a distance that joins more than this is
/// not a weld tolerance but a mistake, and is refused.
constexpr std::size_t kMaxWeldPairsPerVertex = 32;

/// Wraps `source` so that its objects' coincident vertices are welded (kExact
/// or kDistance; kAuto must be resolved by the caller). Reads every frame of
/// `source` once to find them (it stops early when no candidate is left), so
/// the cost is one pass over the cache. Vertices are only joined within an
/// object. A welded vertex takes the position of the smallest file vertex
/// joined into it; triangles keep their ids, so a triangle whose corners were
/// joined stays, with a repeated vertex. Object::weld says which method ran, even
/// when it joined nothing. Returns `source` itself for kNone.
/// Throws what source.read_frame throws, and UsageError when a kDistance
/// weld would examine more than kMaxWeldPairsPerVertex pairs per vertex.
std::unique_ptr<FrameSource> weld_vertices(std::unique_ptr<FrameSource> source, const WeldSettings& settings);

}  // namespace snag::io
