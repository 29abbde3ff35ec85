// ConcurrentUnionFind against a plain serial union-find: random unions on
// eight threads at once, round after round (clear() between them), give the
// same sets, each found at its smallest member (by find() and by root_of(),
// which shortens no path), and a cleared union-find
// holds every id alone whatever the rounds before left in it.
#include "report/concurrent_union_find.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

namespace snag::report {
namespace {

// The smallest member of each id's set, for the pairs joined.
std::vector<std::uint32_t> serial_roots(std::size_t size,
                                        const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
  std::vector<std::uint32_t> parent(size);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t id) {
    while (parent[id] != id) id = parent[id];
    return id;
  };
  for (const auto& [a, b] : pairs) {
    const std::uint32_t ra = find(a), rb = find(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  std::vector<std::uint32_t> roots(size);
  for (std::uint32_t id = 0; id < size; ++id) roots[id] = find(id);
  return roots;
}

TEST(ConcurrentUnionFind, UnitesOnManyThreadsRoundAfterRoundAsASerialUnionFind) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 8);
  constexpr std::size_t kSize = 25000;  // above the last round's ids (12500 + 9000)
  ConcurrentUnionFind<std::uint32_t> sets(kSize);
  std::mt19937 random(7);
  for (int round = 0; round < 6; ++round) {
    sets.clear();
    // Each round joins a different part of the ids (so that the ids the round
    // before joined must read as alone), some of it densely (long chains
    // that the threads share) and some sparsely.
    const std::uint32_t begin = static_cast<std::uint32_t>(round * 2500), span = 9000;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs(round % 2 == 0 ? 12000 : 3000);
    for (auto& [a, b] : pairs) {
      a = begin + static_cast<std::uint32_t>(random() % span);
      b = begin + static_cast<std::uint32_t>(random() % (random() % 4 == 0 ? span : 64));
    }
    tbb::parallel_for(std::size_t{0}, pairs.size(),
                      [&](std::size_t k) { sets.unite(pairs[k].first, pairs[k].second); });
    const std::vector<std::uint32_t> expected = serial_roots(kSize, pairs);
    for (std::uint32_t id = 0; id < kSize; ++id)
      ASSERT_EQ(sets.root_of(id), expected[id]) << "round " << round << " id " << id;
    for (std::uint32_t id = 0; id < kSize; ++id)
      ASSERT_EQ(sets.find(id), expected[id]) << "round " << round << " id " << id;
  }
  sets.clear();
  for (std::uint32_t id = 0; id < kSize; ++id) ASSERT_EQ(sets.find(id), id);
}

}  // namespace
}  // namespace snag::report
