// VertexFans against the brute-force oracle: no pair of triangles sharing an
// apart vertex intersects (triangles_intersect over every pair that shares a
// vertex), on sheets from flat to crumpled enough that neighbours cross;
// flat sheets are apart everywhere; fans that do not chain (a non-manifold
// edge, a repeated id, a duplicated face) or that wind twice are never apart.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "libcd/narrow_phase/vertex_fans.hpp"

namespace snag {
namespace {

struct Sheet {
  std::vector<Vec3> x;
  std::vector<Triangle> triangles;
};

/// A side × side grid of vertices in the xy plane, 1 apart, each moved by up
/// to `jitter` along x and y and up to `bump` along z; quads split along
/// alternating diagonals.
Sheet sheet(unsigned seed, Index side, double jitter, double bump) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  Sheet s;
  for (Index j = 0; j < side; ++j)
    for (Index i = 0; i < side; ++i)
      s.x.push_back({double(i) + jitter * u(rng), double(j) + jitter * u(rng), bump * u(rng)});
  for (Index j = 0; j + 1 < side; ++j) {
    for (Index i = 0; i + 1 < side; ++i) {
      const Index v = j * side + i;
      if ((i + j) % 2 == 0) {
        s.triangles.push_back({v, v + 1, v + side + 1});
        s.triangles.push_back({v, v + side + 1, v + side});
      } else {
        s.triangles.push_back({v, v + 1, v + side});
        s.triangles.push_back({v + 1, v + side + 1, v + side});
      }
    }
  }
  return s;
}

bool intersect(const Sheet& s, std::size_t a, std::size_t b) {
  const Triangle& ta = s.triangles[a];
  const Triangle& tb = s.triangles[b];
  const Vec3 pa[3] = {s.x[ta[0]], s.x[ta[1]], s.x[ta[2]]};
  const Vec3 pb[3] = {s.x[tb[0]], s.x[tb[1]], s.x[tb[2]]};
  return triangles_intersect(pa, ta.data(), pb, tb.data());
}

/// Every pair of triangles sharing a vertex: none that shares an apart one
/// intersects. Returns how many neighbour pairs intersect.
std::size_t expect_apart_pairs_do_not_intersect(const Sheet& s, const std::vector<unsigned char>& apart,
                                                const std::string& what) {
  std::size_t intersecting = 0;
  for (std::size_t a = 0; a < s.triangles.size(); ++a) {
    for (std::size_t b = a + 1; b < s.triangles.size(); ++b) {
      bool shared = false, shared_apart = false;
      for (const Index va : s.triangles[a])
        for (const Index vb : s.triangles[b])
          if (va == vb) {
            shared = true;
            shared_apart = shared_apart || apart[va];
          }
      if (!shared) continue;
      const bool hit = intersect(s, a, b);
      intersecting += hit;
      EXPECT_FALSE(hit && shared_apart) << what << ": triangles " << a << " and " << b
                                        << " intersect but share an apart vertex";
    }
  }
  return intersecting;
}

std::size_t count(const std::vector<unsigned char>& flags) {
  std::size_t n = 0;
  for (const unsigned char f : flags) n += f != 0;
  return n;
}

TEST(VertexFans, FlatSheetsAreApartEverywhere) {
  for (const double jitter : {0.0, 0.4}) {
    const Sheet s = sheet(1, 12, jitter, 0.0);
    const VertexFans fans(s.triangles, s.x.size());
    EXPECT_EQ(fans.chained_count(), s.x.size());
    std::vector<unsigned char> apart;
    fans.find_apart(s.x, apart);
    EXPECT_EQ(count(apart), s.x.size()) << "jitter " << jitter;
  }
}

TEST(VertexFans, NoPairSharingAnApartVertexIntersectsOnCrumpledSheets) {
  std::size_t intersecting = 0, not_apart = 0, apart_total = 0;
  for (unsigned seed : {1u, 2u, 3u}) {
    // Jitter beyond 1 folds the sheet's plan, so that neighbours can cross.
    for (const double jitter : {0.9, 2.5}) {
      for (const double bump : {0.1, 1.0, 3.0, 8.0}) {
        const Sheet s = sheet(seed, 16, jitter, bump);
        const VertexFans fans(s.triangles, s.x.size());
        std::vector<unsigned char> apart;
        fans.find_apart(s.x, apart);
        ASSERT_EQ(apart.size(), s.x.size());
        apart_total += count(apart);
        not_apart += s.x.size() - count(apart);
        intersecting += expect_apart_pairs_do_not_intersect(
            s, apart, "seed " + std::to_string(seed) + ", jitter " + std::to_string(jitter) + ", bump " +
                          std::to_string(bump));
      }
    }
  }
  // The sheets are crumpled enough that some neighbours intersect and some
  // fans fold over, and smooth enough that most fans are apart.
  EXPECT_GT(intersecting, 0u);
  EXPECT_GT(not_apart, 0u);
  EXPECT_GT(apart_total, not_apart);
}

TEST(VertexFans, FansThatDoNotChainAreNeverApart) {
  Sheet s = sheet(2, 6, 0.0, 0.0);
  const std::size_t plain = s.x.size();
  // A third triangle on the edge (7, 8) of the sheet, standing up from it.
  const Index top = static_cast<Index>(s.x.size());
  s.x.push_back({1.5, 1.0, 2.0});
  s.triangles.push_back({7, 8, top});
  // A triangle with a repeated id, at vertex 20 and 21.
  s.triangles.push_back({20, 20, 21});
  // A duplicated face.
  const Triangle duplicated = s.triangles[30];
  s.triangles.push_back(duplicated);
  const VertexFans fans(s.triangles, s.x.size());
  std::vector<unsigned char> apart;
  fans.find_apart(s.x, apart);
  for (const Index v : {Index(7), Index(8), Index(20), Index(21), duplicated[0], duplicated[1], duplicated[2]})
    EXPECT_FALSE(apart[v]) << "vertex " << v;
  EXPECT_TRUE(apart[top]);  // a lone triangle's corner
  EXPECT_GT(count(apart), plain / 2);
}

TEST(VertexFans, FansThatWindTwiceAreNeverApart) {
  // Six triangles around vertex 0 whose ring goes twice around it (120
  // degrees each), the second turn higher: the projected wedges overlap.
  for (const bool closed : {true, false}) {
    Sheet s;
    s.x.push_back({0, 0, 0});
    for (int k = 0; k < 6; ++k) {
      const double angle = 2.0943951023931953 * k + 0.1;
      s.x.push_back({std::cos(angle) * (1 + 0.1 * k), std::sin(angle) * (1 + 0.1 * k), 0.2 * k});
    }
    const Index ring = closed ? 6 : 7;
    if (!closed) s.x.push_back({std::cos(0.3) * 2, std::sin(0.3) * 2, 1.5});
    for (Index k = 0; k < 6; ++k) s.triangles.push_back({0, Index(1 + k), Index(1 + (k + 1) % ring)});
    const VertexFans fans(s.triangles, s.x.size());
    std::vector<unsigned char> apart;
    fans.find_apart(s.x, apart);
    EXPECT_FALSE(apart[0]) << (closed ? "closed" : "open");
    expect_apart_pairs_do_not_intersect(s, apart, closed ? "closed" : "open");
  }
}

}  // namespace
}  // namespace snag
