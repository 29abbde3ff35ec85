// MDD point cache (LightWave; Blender's exporter writes it too).
#pragma once

#include <string>
#include <string_view>

#include "io/point_cache.hpp"

namespace snag::io {

/// Checks an MDD file held in memory and says where its frames lie.
/// Layout (big-endian): int32 numFrames, int32 numPoints, numFrames float32
/// times (seconds), then the frames, each numPoints × float32 xyz.
/// Two layouts exist and are told apart by the file size: N frames of points,
/// or N + 1 where the first is a rest pose (Blender's exporter writes it
/// before the animated frames). The rest pose is skipped: frame i is always
/// the file's i-th animated frame, at time times[i].
/// Throws InputError (naming `file` and the byte) for negative or zero counts,
/// a size that fits neither layout (checked in 64 bits) and non-finite times.
PointCacheLayout parse_mdd_layout(std::string_view bytes, const std::string& file);

}  // namespace snag::io
