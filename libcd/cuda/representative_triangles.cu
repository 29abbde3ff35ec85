// Representative-triangle feature pairs and feature-level DOP culling on the
// GPU: the CUDA twin of libcd/culling/representative_triangles.cpp.
// Curtis, Tamstorf, Manocha, "Fast collision detection for deformable models
// using representative-triangles", I3D 2008; Klosowski et al. 1998 (k-DOPs).
// The screen's early exits with their loops unrolled (see
// libcd/narrow_phase/ccd_separating_direction.hpp).
#define SNAG_CCD_UNROLL_SEPARATION 1
#include "libcd/cuda/representative_triangles.cuh"

#include <cub/block/block_scan.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <string>
#include <vector>

#include "libcd/core/error.hpp"

#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"

namespace snag {
namespace {

using detail::blocks_for;
using detail::exclusive_scan;
using detail::pack_key;
using detail::radix_bits;
using detail::radix_sort_keys;
using detail::thread_item;
using detail::unpack_key;

__device__ __forceinline__ bool is_corner(const Triangle& t, Index v) { return t[0] == v || t[1] == v || t[2] == v; }

struct FeatureInputs {
  const Triangle* tris;
  const Edge* edges;
  const std::uint8_t* masks;
  const std::array<Index, 3>* edge_ids;
  const Dop18* triangle_dops;
  const Dop18* edge_dops;
  const Dop18* vertex_dops;
  const FloatBox* triangle_boxes;
  const FloatBox* edge_boxes;
  const FloatBox* vertex_boxes;
  const TrianglePair* pairs;
};

/// Whether the screen's early exits decide feature pair (x, y) kNo: vertex x
/// against face y, or edges x and y, with their points in the order the
/// narrow phase reads its candidate's (the smaller edge first), so that
/// the decision is the one it would take.
__device__ bool screened_out(const FeatureInputs& in, const FeatureScreen& screen, Index x, Index y, bool edges) {
  Index ids[4];
  if (edges) {
    const Edge a = in.edges[x < y ? x : y], b = in.edges[x < y ? y : x];
    ids[0] = a[0];
    ids[1] = a[1];
    ids[2] = b[0];
    ids[3] = b[1];
  } else {
    const Triangle face = in.tris[y];
    ids[0] = x;
    ids[1] = face[0];
    ids[2] = face[1];
    ids[3] = face[2];
  }
  Vec3 p[8];
  for (int k = 0; k < 4; ++k) {
    p[k] = screen.x_t0[ids[k]];
    p[4 + k] = screen.x_t1[ids[k]];
  }
  CcdResult result;
  const bool decided =
      edges ? edge_edge_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], screen.settings, &result)
            : vertex_face_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], screen.settings, &result);
  return decided && result.answer == CcdAnswer::kNo;
}

/// A feature pair whose float boxes meet, waiting for its DOP test: a vertex
/// (or edge) x and a triangle (or edge) y, the lane whose triangle pair it
/// belongs to and its kept bit.
struct WaitingFeaturePair {
  Index x, y;
  std::uint32_t lane_bit;  ///< lane << 8 | kept bit << 1 | edge-edge
};

/// Counts the feature pairs of triangle pair p < n before and after culling
/// (tally[p]; tally[n] is zero; the sums of all pairs in counters[0] and [1]
/// before, vertex-face and edge-edge, and with count_kept in [4] and [5]
/// after) and records which the culling kept (kept[p]; kept bit:
/// vertex-face 3 s + i, edge-edge 6 + 3 i + j), so that
/// write_kernel need not test them again:
/// the CPU's loop body, one pair a thread. The DOPs' float boxes are tested
/// first: where they are apart the DOPs are (float_box.hpp), and most culled
/// pairs are apart in x, y or z already. The feature pairs whose boxes meet
/// wait in their warp's list in shared memory until it holds 32, whose DOPs
/// the warp then tests with all its lanes (a lane's boxes meet for a few of
/// its 15 feature pairs, at other places than its neighbours'). Every thread
/// of a block runs every step, so warp-wide operations see full warps.
/// Four blocks a multiprocessor (64 registers, a few spilled): on cloth_ball
/// 345 µs, against 377 with the 84 registers it takes unbounded (H200).
__global__ void __launch_bounds__(detail::kBlockSize, 4)
    count_kernel(FeatureInputs in, std::size_t n, bool count_kept, FeatureTally* tally, std::uint16_t* kept,
                 unsigned long long* counters) {
  __shared__ WaitingFeaturePair warp_waiting[detail::kBlockSize / 32][64];
  __shared__ unsigned warp_kept[detail::kBlockSize / 32][32];
  const unsigned lane = threadIdx.x & 31u;
  WaitingFeaturePair* const waiting = warp_waiting[threadIdx.x / 32];
  unsigned* const kept_bits = warp_kept[threadIdx.x / 32];
  kept_bits[lane] = 0;
  __syncwarp();
  unsigned waiting_count = 0;  // the same on every lane of the warp
  // Tests the DOPs of the first m (at most 32) waiting pairs, a pair a lane,
  // and drops them from the list.
  auto test_waiting = [&](unsigned m) {
    if (lane < m) {
      const WaitingFeaturePair w = waiting[lane];
      const bool edges = w.lane_bit & 1u;
      if (dop_overlap(read_dop(edges ? in.edge_dops : in.vertex_dops, w.x),
                      read_dop(edges ? in.edge_dops : in.triangle_dops, w.y)))
        atomicOr(&kept_bits[w.lane_bit >> 8], 1u << ((w.lane_bit >> 1) & 127u));
    }
    detail::warp_list_drop(waiting, waiting_count, m);
  };
  // Appends the feature pairs of the lanes with `take` set to the list.
  auto push = [&](bool take, Index x, Index y, unsigned bit, bool edges) {
    const WaitingFeaturePair pair{x, y, lane << 8 | bit << 1 | edges};
    detail::warp_list_push(take, pair, waiting, waiting_count);
    if (waiting_count >= 32) test_waiting(32);
  };

  const std::uint64_t p = thread_item();
  const bool in_range = p < n;
  unsigned vf_before = 0, ee_before = 0;
  Index side[2] = {0, 0};
  if (in_range) {
    side[0] = in.pairs[p].a;
    side[1] = in.pairs[p].b;
  }
  const Triangle t[2] = {in.tris[side[0]], in.tris[side[1]]};
  const std::uint8_t masks[2] = {in_range ? in.masks[side[0]] : std::uint8_t{0},
                                 in_range ? in.masks[side[1]] : std::uint8_t{0}};
  // Each box and edge is read only where the masks ask for it: the kernel
  // is bound by its scattered reads.
#pragma unroll
  for (int s = 0; s < 2; ++s) {
    const Index face = side[1 - s];
    const FloatBox face_box = (masks[s] & 7u) != 0 ? read_box(in.triangle_boxes, face) : FloatBox{};
    for (int i = 0; i < 3; ++i) {
      const Index v = t[s][i];
      bool take = false;
      if ((masks[s] & (1u << i)) && !is_corner(t[1 - s], v)) {
        ++vf_before;
        take = float_boxes_may_overlap(read_box(in.vertex_boxes, v), face_box);
      }
      push(take, v, face, 3 * s + i, false);
    }
  }
  // Edge-edge: a's edges one at a time, b's read again for each (from the
  // cache): holding a's three edges and boxes spilled more (208 -> 128
  // bytes of spill loads; count_kernel, H200: cloth_ball ×4 2.22 -> 2.14
  // ms, ×16 14.5 -> 14.1 ms a step).
  const std::array<Index, 3> edges_a = in.edge_ids[side[0]], edges_b = in.edge_ids[side[1]];
  for (int i = 0; i < 3; ++i) {
    const bool kept_a = masks[0] & (1u << (3 + i));
    const Edge ga = kept_a ? in.edges[edges_a[i]] : Edge{};
    const FloatBox box_a = kept_a ? read_box(in.edge_boxes, edges_a[i]) : FloatBox{};
    for (int j = 0; j < 3; ++j) {
      const Index eb = edges_b[j];
      bool take = false;
      if (kept_a && (masks[1] & (1u << (3 + j)))) {
        const Edge gb = in.edges[eb];
        if (!(ga[0] == gb[0] || ga[0] == gb[1] || ga[1] == gb[0] || ga[1] == gb[1])) {
          ++ee_before;
          take = float_boxes_may_overlap(box_a, read_box(in.edge_boxes, eb));
        }
      }
      push(take, edges_a[i], eb, 6 + 3 * i + j, true);
    }
  }
  if (waiting_count > 0) test_waiting(waiting_count);
  __syncwarp();
  unsigned vf_kept = 0, ee_kept = 0;
  if (in_range) {
    const unsigned bits = kept_bits[lane];
    vf_kept = static_cast<unsigned>(__popc(bits & 63u));
    ee_kept = static_cast<unsigned>(__popc(bits >> 6));
    kept[p] = static_cast<std::uint16_t>(bits);
    tally[p] = {vf_kept, ee_kept};
  } else if (p == n) {
    tally[p] = {0, 0};
  }
  detail::warp_count(vf_before, &counters[0]);
  detail::warp_count(ee_before, &counters[1]);
  if (count_kept) {  // the same on every thread
    detail::warp_count(vf_kept, &counters[4]);
    detail::warp_count(ee_kept, &counters[5]);
  }
}

/// The screen (FeatureScreen) of the feature pairs count_kernel kept of
/// triangle pairs p < n: the early exits run on each, and those they decide
/// kNo leave kept[p], tally[p] is counted again, and counters[2]
/// (vertex-face) and counters[3] (edge-edge) count them. With
/// screen.only_above, the whole grid returns at once when count_kernel's
/// sums (counters[4], [5]) are each at most that many and together at most
/// part_step (one part): the decision is taken on the device, so that the
/// host need not wait for the counts first. A block takes kScreenPairs
/// pairs (kScreenPairsPerThread a thread, a block's width apart), lists their
/// vertex-face pairs, then their edge-edge pairs, in one list in shared
/// memory, and screens the list a thread an item. The early exits' cost
/// varies from item to item, and a block waits for its slowest warp at the
/// barrier after the list: with 1.6 feature pairs a triangle pair (the
/// refined cloths), a block of a thread a pair and a list of each kind
/// spent a third of its warps' cycles there (×4, ncu). On ×4 (H200, ncu)
/// the kernel took 3.35 ms so, 2.47 with this block and the early exits'
/// products and sums contracted (libcd/cuda/CMakeLists.txt), 1.74 with
/// their loops unrolled too (SNAG_CCD_UNROLL_SEPARATION). A thread that looped
/// over its own pair's bits held its warp for its neighbours' longest list,
/// through both kinds' code (×16: about four times as long). A kernel of its
/// own: the early exits need more registers than count_kernel's bound
/// leaves (inside it they spilled some 19 kB); 128 a thread, as the narrow
/// phase's early-exit kernel.
constexpr unsigned kScreenBlock = 256;
constexpr unsigned kScreenPairsPerThread = 4;
constexpr unsigned kScreenPairs = kScreenBlock * kScreenPairsPerThread;
static_assert(kScreenPairs <= (1u << 12) && kMostCandidatesPerPair <= 16,
              "a list item is a pair's slot above its bit in 16 bits");
__global__ void __launch_bounds__(kScreenBlock, 2)
    screen_kernel(FeatureInputs in, FeatureScreen screen, std::uint64_t part_step, std::size_t n,
                  FeatureTally* tally, std::uint16_t* kept, unsigned long long* counters) {
  if (!screen.runs(counters[4], counters[5], part_step)) return;  // the same answer on every thread
  using Scan = cub::BlockScan<unsigned, kScreenBlock>;
  __shared__ typename Scan::TempStorage scan_storage;
  __shared__ Index sides[kScreenPairs][2];
  __shared__ unsigned cleared[kScreenPairs];  // the bits each pair loses
  // The items: a pair's slot in the block above its kept bit (0..14), the
  // vertex-face pairs first.
  __shared__ std::uint16_t items[kScreenPairs * kMostCandidatesPerPair];
  const std::uint64_t first_pair = static_cast<std::uint64_t>(blockIdx.x) * kScreenPairs;
  // A pair's kept bits, read again where needed: kept four a thread for the
  // whole kernel they made the early exits spill.
  auto kept_bits = [&](unsigned slot) { return first_pair + slot < n ? unsigned{kept[first_pair + slot]} : 0u; };
  unsigned counts = 0;  // vertex-face below, edge-edge above bit 16 (at most 6 and 9 a pair)
#pragma unroll
  for (unsigned r = 0; r < kScreenPairsPerThread; ++r) {
    const unsigned slot = r * kScreenBlock + threadIdx.x;
    const unsigned bits = kept_bits(slot);
    if (bits != 0) {
      const TrianglePair pair = in.pairs[first_pair + slot];
      sides[slot][0] = pair.a;
      sides[slot][1] = pair.b;
    }
    cleared[slot] = 0;
    counts += static_cast<unsigned>(__popc(bits & 63u)) | static_cast<unsigned>(__popc(bits >> 6)) << 16;
  }
  unsigned first = 0, totals = 0;
  Scan(scan_storage).ExclusiveSum(counts, first, totals);  // no carry: at most 6 · kScreenPairs below bit 16
  if (totals == 0) return;  // the whole block
  const unsigned vf_total = totals & 0xffffu, total = vf_total + (totals >> 16);
  unsigned vf_at = first & 0xffffu, ee_at = vf_total + (first >> 16);
#pragma unroll
  for (unsigned r = 0; r < kScreenPairsPerThread; ++r) {
    const unsigned slot = r * kScreenBlock + threadIdx.x, bits = kept_bits(slot);
    for (unsigned mine = bits & 63u; mine != 0; mine &= mine - 1)
      items[vf_at++] = static_cast<std::uint16_t>(slot << 4 | static_cast<unsigned>(__ffs(mine) - 1));
    for (unsigned mine = bits >> 6; mine != 0; mine &= mine - 1)
      items[ee_at++] = static_cast<std::uint16_t>(slot << 4 | static_cast<unsigned>(__ffs(mine) + 5));
  }
  __syncthreads();  // the list, the sides and the cleared bits are written
  unsigned screened[2] = {0, 0};  // vertex-face, edge-edge
  for (unsigned k = threadIdx.x; k < total; k += kScreenBlock) {
    const unsigned slot = items[k] >> 4, bit = items[k] & 15u;
    const Index a = sides[slot][0], b = sides[slot][1];
    const bool edges = bit >= 6;
    bool out = false;
    if (!edges) {  // vertex i of side s against the other side's face
      const unsigned s = bit / 3, i = bit % 3;
      out = screened_out(in, screen, in.tris[s == 0 ? a : b][i], s == 0 ? b : a, false);
    } else {  // edge i of side 0 against edge j of side 1
      const unsigned e = bit - 6;
      out = screened_out(in, screen, in.edge_ids[a][e / 3], in.edge_ids[b][e % 3], true);
    }
    if (out) {
      atomicOr(&cleared[slot], 1u << bit);
      ++screened[edges];
    }
  }
  __syncthreads();  // the cleared bits are final
#pragma unroll
  for (unsigned r = 0; r < kScreenPairsPerThread; ++r) {
    const unsigned slot = r * kScreenBlock + threadIdx.x, bits = kept_bits(slot);
    if (bits == 0) continue;
    const unsigned left = bits & ~cleared[slot];
    const std::uint64_t p = first_pair + slot;
    kept[p] = static_cast<std::uint16_t>(left);
    tally[p] = {static_cast<std::uint64_t>(__popc(left & 63u)), static_cast<std::uint64_t>(__popc(left >> 6))};
  }
  detail::warp_count(screened[0], &counters[2]);
  detail::warp_count(screened[1], &counters[3]);
}

/// The low_bits of the feature keys (pack_key): a face's id below the vertex
/// in a vertex-face key, the larger edge below the smaller in an edge-edge key.
struct FeatureKeyBits {
  int face, edge;
};

/// Writes the keys of the kept feature pairs of pairs [first, first + n)
/// (vertex << bits.face | face, edge_a << bits.edge | edge_b with edge_a <
/// edge_b), in the order count_kernel finds them, at their offsets less
/// those of pair `first`.
__global__ void write_kernel(FeatureInputs in, std::uint64_t first, std::size_t n, const std::uint16_t* kept,
                             const FeatureTally* offset, FeatureKeyBits bits, std::uint64_t* vf_keys,
                             std::uint64_t* ee_keys) {
  const std::uint64_t k = thread_item();
  if (k >= n) return;
  const std::uint64_t p = first + k;
  const unsigned kept_bits = kept[p];
  if (kept_bits == 0) return;
  const Index side[2] = {in.pairs[p].a, in.pairs[p].b};
  std::uint64_t* vf = vf_keys + (offset[p].vf - offset[first].vf);
  for (int s = 0; s < 2; ++s) {
    if (!(kept_bits & (7u << (3 * s)))) continue;
    const Triangle ta = in.tris[side[s]];
    for (int i = 0; i < 3; ++i)
      if (kept_bits & (1u << (3 * s + i))) *vf++ = pack_key(ta[i], side[1 - s], bits.face);
  }
  if (!(kept_bits >> 6)) return;
  std::uint64_t* ee = ee_keys + (offset[p].ee - offset[first].ee);
  const std::array<Index, 3> edges_a = in.edge_ids[side[0]], edges_b = in.edge_ids[side[1]];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!(kept_bits & (1u << (6 + 3 * i + j)))) continue;
      const Index ea = edges_a[i], eb = edges_b[j];
      *ee++ = ea < eb ? pack_key(ea, eb, bits.edge) : pack_key(eb, ea, bits.edge);
    }
  }
}

/// Part j (0 <= j <= parts) starts at the first pair whose candidates before
/// it number at least j * step (part `parts` at n); bounds[3j..3j+2] = that
/// pair and its vertex-face and edge-edge offsets.
__global__ void part_bounds_kernel(const FeatureTally* offset, std::size_t n, std::uint64_t step, std::size_t parts,
                                   std::uint64_t* bounds) {
  const std::uint64_t j = thread_item();
  if (j > parts) return;
  std::uint64_t lo = 0, hi = n;  // the first p in [0, n] with offset(p) >= j * step
  if (j == parts) {
    lo = n;
  } else {
    while (lo < hi) {
      const std::uint64_t mid = lo + (hi - lo) / 2;
      if (offset[mid].vf + offset[mid].ee >= j * step)
        hi = mid;
      else
        lo = mid + 1;
    }
  }
  bounds[3 * j] = lo;
  bounds[3 * j + 1] = offset[lo].vf;
  bounds[3 * j + 2] = offset[lo].ee;
}

struct AddFeatureTallies {
  __device__ FeatureTally operator()(const FeatureTally& a, const FeatureTally& b) const {
    return {a.vf + b.vf, a.ee + b.ee};
  }
};

__global__ void unpack_vf_kernel(const std::uint64_t* keys, std::size_t n, int bits, VertexFaceCandidate* out) {
  const std::uint64_t k = thread_item();
  if (k < n) unpack_key(keys[k], bits, out[k].vertex, out[k].face);
}
__global__ void unpack_ee_kernel(const std::uint64_t* keys, std::size_t n, int bits, EdgeEdgeCandidate* out) {
  const std::uint64_t k = thread_item();
  if (k < n) unpack_key(keys[k], bits, out[k].edge_a, out[k].edge_b);
}

/// Sorts n keys with `spare` as the sort's other half; returns the half that holds them sorted.
const std::uint64_t* sort_keys(std::uint64_t* keys, std::uint64_t* spare, std::size_t n, int end_bit,
                               DeviceBuffer<unsigned char>& temp, cudaStream_t stream) {
  if (n == 0) return keys;
  cub::DoubleBuffer<std::uint64_t> halves(keys, spare);
  radix_sort_keys(halves, n, end_bit, temp, stream);
  return halves.Current();
}

}  // namespace

void representative_feature_pairs_on_device(
    const DeviceTopology& topology, const DevicePrimitiveBounds& bounds, std::size_t vertex_count,
    std::size_t edge_count, const TrianglePair* pairs, std::size_t n, std::size_t candidate_room, DeviceFeatures& f,
    cudaStream_t stream, FeatureCounts& counts,
    const std::function<void(const VertexFaceCandidate*, std::size_t, const EdgeEdgeCandidate*, std::size_t)>& visit,
    bool sorted, const FeatureScreen* screen) {
  if (n == 0) return;
  if (candidate_room <= kMostCandidatesPerPair)
    throw UsageError("the device memory limit is too small for this scene: the feature stage has room for " +
                     std::to_string(candidate_room) + " candidates; raise the limit (snag-scan --device-memory)");
  const FeatureInputs in{topology.triangles.data(),
                         topology.edges.data(),
                         topology.masks.data(),
                         topology.edge_ids.data(),
                         bounds.triangles.data(),
                         bounds.edges.data(),
                         bounds.vertices.data(),
                         bounds.triangle_boxes.data(),
                         bounds.edge_boxes.data(),
                         bounds.vertex_boxes.data(),
                         pairs};
  f.kept.resize(n);
  f.counters.resize(6);
  f.tally.resize(n + 1);
  f.counters.fill_zero();
  const bool decide_screen = screen != nullptr && screen->only_above > 0;
  count_kernel<<<blocks_for(n + 1), detail::kBlockSize, 0, stream>>>(in, n, decide_screen, f.tally.data(),
                                                                      f.kept.data(), f.counters.data());
  SNAG_CUDA_CHECK_LAUNCH();
  // Parts of consecutive pairs: a part starts where the candidates before it
  // reach a multiple of step, so it holds fewer than step + 15 <= room. One
  // part (the usual case) is all the pairs, and needs no search.
  const std::uint64_t step = candidate_room - kMostCandidatesPerPair;
  if (screen != nullptr) {
    screen_kernel<<<static_cast<unsigned>((n + kScreenPairs - 1) / kScreenPairs), kScreenBlock, 0, stream>>>(
        in, *screen, step, n, f.tally.data(), f.kept.data(), f.counters.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }
  exclusive_scan(f.tally.data(), f.tally.data(), n + 1, AddFeatureTallies{}, f.temp, stream);
  FeatureTally total;
  // Before the DOPs, screened out, kept by the DOPs (vertex-face, edge-edge;
  // the last two only where the screen decides whether it runs).
  unsigned long long sums[6] = {0, 0, 0, 0, 0, 0};
  ReadBack(stream).add(&total, f.tally.data() + n).add(sums, f.counters.data(), 6).wait();
  f.screened = screen != nullptr && screen->runs(sums[4], sums[5], step);
  counts.vf_before += sums[0];
  counts.ee_before += sums[1];
  counts.vf_after += total.vf + sums[2];
  counts.ee_after += total.ee + sums[3];

  const std::uint64_t candidates = total.vf + total.ee;
  const std::size_t parts = std::max<std::uint64_t>(1, candidates / step + (candidates % step != 0 ? 1 : 0));
  std::vector<std::uint64_t> part_bounds(3 * (parts + 1));
  if (parts == 1) {
    part_bounds = {0, 0, 0, n, total.vf, total.ee};
  } else {
    f.bounds.resize(part_bounds.size());
    part_bounds_kernel<<<blocks_for(parts + 1), detail::kBlockSize, 0, stream>>>(f.tally.data(), n, step, parts,
                                                                                 f.bounds.data());
    SNAG_CUDA_CHECK_LAUNCH();
    f.bounds.download(part_bounds.data(), part_bounds.size());
    SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  }

  // Keys are unique (see representative_triangles.hpp); a sort orders them
  // as the CPU's (unless `sorted` is false).
  const std::size_t triangle_count = topology.triangles.size();
  const FeatureKeyBits bits{radix_bits(triangle_count > 0 ? triangle_count - 1 : 0),
                            radix_bits(edge_count > 0 ? edge_count - 1 : 0)};
  const int vf_bits = bits.face + radix_bits(vertex_count > 0 ? vertex_count - 1 : 0), ee_bits = 2 * bits.edge;
  for (std::size_t j = 0; j < parts; ++j) {
    const std::uint64_t first = part_bounds[3 * j], end = part_bounds[3 * j + 3];
    const std::size_t vf_n = part_bounds[3 * j + 4] - part_bounds[3 * j + 1],
                      ee_n = part_bounds[3 * j + 5] - part_bounds[3 * j + 2];
    if (end == first) continue;
    f.vf_keys.resize(vf_n);
    f.ee_keys.resize(ee_n);
    f.vf_sorted.resize(sorted ? vf_n : 0);
    f.ee_sorted.resize(sorted ? ee_n : 0);
    write_kernel<<<blocks_for(end - first), detail::kBlockSize, 0, stream>>>(
        in, first, end - first, f.kept.data(), f.tally.data(), bits, f.vf_keys.data(), f.ee_keys.data());
    SNAG_CUDA_CHECK_LAUNCH();
    const std::uint64_t* vf_sorted =
        sorted ? sort_keys(f.vf_keys.data(), f.vf_sorted.data(), vf_n, vf_bits, f.temp, stream) : f.vf_keys.data();
    const std::uint64_t* ee_sorted =
        sorted ? sort_keys(f.ee_keys.data(), f.ee_sorted.data(), ee_n, ee_bits, f.temp, stream) : f.ee_keys.data();
    f.vf.resize(vf_n);
    f.ee.resize(ee_n);
    if (vf_n > 0) {
      unpack_vf_kernel<<<blocks_for(vf_n), detail::kBlockSize, 0, stream>>>(vf_sorted, vf_n, bits.face, f.vf.data());
      SNAG_CUDA_CHECK_LAUNCH();
    }
    if (ee_n > 0) {
      unpack_ee_kernel<<<blocks_for(ee_n), detail::kBlockSize, 0, stream>>>(ee_sorted, ee_n, bits.edge, f.ee.data());
      SNAG_CUDA_CHECK_LAUNCH();
    }
    SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
    visit(f.vf.data(), vf_n, f.ee.data(), ee_n);
  }
}

}  // namespace snag
