// What a broad phase outputs: vertex-face and edge-edge candidates for CCD,
// triangle pairs for static detection. Global ids of snag::Scene.
#pragma once

#include <cstdint>
#include <tuple>

#include "libcd/core/host_device.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

/// Vertex `vertex` against triangle `face`; the vertex is never a corner of the face.
struct VertexFaceCandidate {
  Index vertex = 0;
  Index face = 0;
};
/// Edge `edge_a` against edge `edge_b`, edge_a < edge_b, no common endpoint.
struct EdgeEdgeCandidate {
  Index edge_a = 0;
  Index edge_b = 0;
};
/// Triangles a < b (they may share vertices).
struct TrianglePair {
  Index a = 0;
  Index b = 0;
};

inline bool operator<(VertexFaceCandidate p, VertexFaceCandidate q) {
  return std::tie(p.vertex, p.face) < std::tie(q.vertex, q.face);
}
inline bool operator==(VertexFaceCandidate p, VertexFaceCandidate q) { return p.vertex == q.vertex && p.face == q.face; }
inline bool operator<(EdgeEdgeCandidate p, EdgeEdgeCandidate q) {
  return std::tie(p.edge_a, p.edge_b) < std::tie(q.edge_a, q.edge_b);
}
inline bool operator==(EdgeEdgeCandidate p, EdgeEdgeCandidate q) { return p.edge_a == q.edge_a && p.edge_b == q.edge_b; }
inline bool operator<(TrianglePair p, TrianglePair q) { return std::tie(p.a, p.b) < std::tie(q.a, q.b); }
inline bool operator==(TrianglePair p, TrianglePair q) { return p.a == q.a && p.b == q.b; }

/// A triangle pair packed in 64 bits (a < b), for sorting.
SNAG_HD_INLINE std::uint64_t pack_pair(Index a, Index b) {
  return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}
SNAG_HD_INLINE TrianglePair unpack_pair(std::uint64_t key) {
  return {static_cast<Index>(key >> 32), static_cast<Index>(key & 0xffffffffu)};
}

}  // namespace snag
