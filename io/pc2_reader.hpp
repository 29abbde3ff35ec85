// PC2 point cache (3ds Max / Blender "POINTCACHE2").
#pragma once

#include <string>
#include <string_view>

#include "io/point_cache.hpp"

namespace snag::io {

/// Checks a PC2 file held in memory and says where its frames lie.
/// Layout (little-endian): char[12] "POINTCACHE2\0", int32 version (1),
/// int32 numPoints, float32 startFrame, float32 sampleRate, int32 numSamples,
/// then numSamples × numPoints × float32 xyz. sampleRate is the step between
/// samples in frames (as 3ds Max defines it and Blender writes it), so sample
/// i is at frame startFrame + i × sampleRate.
/// Throws InputError (naming `file` and the byte) for a bad magic or version,
/// negative counts, a non-finite start or a step that is not positive, and a
/// size that differs from what the counts need (checked in 64 bits).
PointCacheLayout parse_pc2_layout(std::string_view bytes, const std::string& file);

}  // namespace snag::io
