// Which faces and frames the HTML page's 3D view draws, within a size budget.
// Faces within a margin of a region keep full resolution; the faces away
// from every region are sampled (every k-th face, k doubling until the
// geometry fits); when even the faces near the regions do not fit, the least
// important frames are dropped, and with one frame left the faces near the
// regions are sampled too. The faces of the regions themselves are always
// drawn.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "exporters/html.hpp"
#include "report/records.hpp"

namespace snag::exporters {

/// A region as the 3D view colours it.
struct ViewRegion {
  std::size_t frame_slot = 0;  ///< index into HtmlScene::frames
  report::Bounds bounds;       ///< the report's bounds of the region
  /// Per object of the scene: the region's local face ids (empty for the
  /// objects it does not touch).
  std::vector<std::vector<std::size_t>> faces;
};

struct ViewSelection {
  std::size_t frames = 0;                          ///< HtmlScene::frames[0, frames) are drawn
  std::vector<std::vector<std::uint32_t>> faces;   ///< per object: the face ids drawn, ascending
  bool decimated = false;                          ///< some faces of the drawn frames' meshes are left out
};

/// Bytes of page text that `faces` of `scene` take with `frames` frames:
/// float32 positions of the vertices they use and uint32 triangles, base64.
std::size_t view_bytes(const HtmlScene& scene, const std::vector<std::vector<std::uint32_t>>& faces,
                       std::size_t frames);

/// Chooses the faces and frames of `scene` to draw in at most `budget` bytes
/// (view_bytes). The margin around a region's bounds is half its diagonal,
/// and at least 5 % of the diagonal of the frame's bounding box. The scene
/// must be consistent (html.cpp checks it). Keeps at least one frame and the
/// faces of its regions even over the budget.
ViewSelection select_view(const HtmlScene& scene, const std::vector<ViewRegion>& regions, std::size_t budget);

}  // namespace snag::exporters
