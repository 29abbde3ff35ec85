// The CCD early exits as the CUDA feature stage's screen runs them, with
// fused multiply-adds (contracted_early_exits.hpp; libcd/cuda/CMakeLists.txt
// says why the screen is built so): still conservative. On every query of the
// exact ground-truth sets (../shared/data/ccd-queries) they rule out no pair
// that touches, and on random pairs near contact, at thickness 0 and above
// it, every pair they rule out is apart by more than the thickness for the
// exact method (validate/exact_ccd.hpp). And the helper that runs them is
// contracted indeed: a product and sum that contraction changes comes out
// rounded once.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "contracted_early_exits.hpp"
#include "gpu_test.hpp"
#include "io/ccd_query_csv.hpp"
#include "validate/exact_ccd.hpp"

namespace snag {
namespace {

using ScreenContraction = test::GpuTest;

TEST_F(ScreenContraction, ProductAndSumAreRoundedOnce) {
  // (1 + 2^-30)(1 - 2^-30) - 1 = -2^-60; rounding the product first gives 1 - 1 = 0.
  const double a = 1 + std::ldexp(1.0, -30), b = 1 - std::ldexp(1.0, -30);
  EXPECT_EQ(test::contracted_multiply_add(a, b, -1.0), -std::ldexp(1.0, -60));
}

TEST_F(ScreenContraction, RuleOutNoContactOfTheGroundTruthQueries) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  ASSERT_GT(queries.size(), 1000u);
  std::vector<test::EarlyExitQuery> batch;
  for (const io::CcdQuery& q : queries) batch.push_back({q.points, q.is_edge_edge});
  const std::vector<bool> ruled_out = test::contracted_early_exits_rule_out(batch, CcdSettings{});
  std::size_t negatives = 0, negatives_ruled_out = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (queries[i].truth) {
      EXPECT_FALSE(ruled_out[i]) << queries[i].file << ":" << queries[i].line << " touches";
    } else {
      ++negatives;
      negatives_ruled_out += ruled_out[i];
    }
  }
  // The set's negatives are hard (coplanar, parallel, grazing), but the
  // early exits decide some: the kernel ran.
  ASSERT_GT(negatives, 100u);
  EXPECT_GT(negatives_ruled_out, 0u);
}

/// Random queries of one kind near contact, of features about `size` across
/// and up to 1e3 from the origin: a triangle (or an edge) in the plane
/// z = 0, moved a little, and a vertex (or an edge) above it that crosses,
/// grazes or stops short of it by about `gap` (in units of size).
std::vector<test::EarlyExitQuery> near_contact_queries(std::mt19937_64& rng, std::size_t count, bool edge_edge,
                                                        double size, double gap) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<test::EarlyExitQuery> queries;
  for (std::size_t q = 0; q < count; ++q) {
    const Vec3 offset{1e3 * unit(rng), 1e3 * unit(rng), 1e3 * unit(rng)};
    // The moving feature's height at t = 0, and at t = 1 from -1/2 to 3/2 times it.
    const double height = gap + 0.02 * unit(rng);
    const Vec3 move{0.1 * unit(rng), 0.1 * unit(rng), height * (unit(rng) - 0.5)};
    Vec3 p[8];
    if (!edge_edge) {
      p[0] = {0.3 * unit(rng), 0.3 * unit(rng), height};
      p[1] = {-1, -1, 0};
      p[2] = {1, -1, 0};
      p[3] = {0, 1, 0};
      p[4] = p[0] + move;
    } else {
      p[0] = {-1, 0.3 * unit(rng), height};
      p[1] = {1, 0.3 * unit(rng), height};
      p[2] = {0.3 * unit(rng), -1, 0};
      p[3] = {0.3 * unit(rng), 1, 0};
      p[4] = p[0] + move;
      p[5] = p[1] + move;
    }
    for (int k = edge_edge ? 2 : 1; k < 4; ++k) p[4 + k] = p[k] + Vec3{0.05 * unit(rng), 0.05 * unit(rng), 0.01 * unit(rng)};
    test::EarlyExitQuery query;
    query.edge_edge = edge_edge;
    for (int k = 0; k < 8; ++k) query.points[k] = offset + size * p[k];
    queries.push_back(query);
  }
  return queries;
}

TEST_F(ScreenContraction, RuleOutOnlyPairsApartByTheThicknessNearContact) {
  std::mt19937_64 rng(41);
  for (const double thickness : {0.0, 0.01}) {  // in units of the features' size
    std::size_t checked = 0, ruled_out_count = 0, collide_count = 0;
    for (const bool edge_edge : {false, true}) {
      for (const double size : {1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3}) {
        const std::vector<test::EarlyExitQuery> queries = near_contact_queries(rng, 150, edge_edge, size, thickness);
        CcdSettings settings;
        settings.thickness = thickness * size;
        const std::vector<bool> ruled_out = test::contracted_early_exits_rule_out(queries, settings);
        for (std::size_t i = 0; i < queries.size(); ++i) {
          const validate::ExactCcdResult exact =
              edge_edge ? validate::exact_edge_edge_ccd(queries[i].points, settings.thickness)
                        : validate::exact_vertex_face_ccd(queries[i].points, settings.thickness);
          ++checked;
          collide_count += exact.collides;
          ruled_out_count += ruled_out[i];
          if (ruled_out[i]) {
            EXPECT_FALSE(exact.collides) << (edge_edge ? "edge-edge" : "vertex-face") << " query " << i << " of size "
                                         << size << " at thickness " << settings.thickness;
          }
        }
      }
    }
    // Both answers are common: the case holds the early exits at their margin.
    EXPECT_GT(ruled_out_count, checked / 10) << "thickness " << thickness;
    EXPECT_GT(collide_count, checked / 10) << "thickness " << thickness;
  }
}

}  // namespace
}  // namespace snag
