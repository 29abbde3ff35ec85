// Mesh elements. Vertex ids are 0-based and local to their object unless a
// comment says "global" (the scene concatenates its objects' vertices).
#pragma once

#include <array>
#include <cstdint>

namespace snag {

using Index = std::uint32_t;
/// Three vertex ids, counter-clockwise as read.
using Triangle = std::array<Index, 3>;
/// Two vertex ids, smaller first.
using Edge = std::array<Index, 2>;

}  // namespace snag
