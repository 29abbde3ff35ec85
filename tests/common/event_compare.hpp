// Comparison of two back ends' results (or of two paths to the same events):
// the same event vectors bit for bit (kind, type, ids, times of impact,
// positions, certainty) and the same narrow-phase counts.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "libcd/pipeline/backend.hpp"

namespace snag::test {

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline void expect_same_events(const std::vector<Event>& cpu, const std::vector<Event>& gpu, const std::string& where) {
  ASSERT_EQ(cpu.size(), gpu.size()) << where;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const Event& c = cpu[i];
    const Event& g = gpu[i];
    const bool same = c.kind == g.kind && c.type == g.type && c.frame == g.frame && c.a == g.a && c.b == g.b &&
                      same_bits(c.toi_lo, g.toi_lo) && same_bits(c.toi_hi, g.toi_hi) &&
                      same_bits(c.position.x, g.position.x) && same_bits(c.position.y, g.position.y) &&
                      same_bits(c.position.z, g.position.z) && c.certainty == g.certainty;
    EXPECT_TRUE(same) << where << ": event " << i << " differs: cpu (" << int(c.type) << ", " << c.a << ", " << c.b
                      << ", toi [" << c.toi_lo << ", " << c.toi_hi << "]) gpu (" << int(g.type) << ", " << g.a
                      << ", " << g.b << ", toi [" << g.toi_lo << ", " << g.toi_hi << "])";
    if (!same) return;
  }
}

inline void expect_same_counts(const NarrowPhaseStats& cpu, const NarrowPhaseStats& gpu, const std::string& where) {
  EXPECT_EQ(cpu.vf_tests, gpu.vf_tests) << where;
  EXPECT_EQ(cpu.vf_yes, gpu.vf_yes) << where;
  EXPECT_EQ(cpu.vf_no, gpu.vf_no) << where;
  EXPECT_EQ(cpu.vf_uncertain, gpu.vf_uncertain) << where;
  EXPECT_EQ(cpu.ee_tests, gpu.ee_tests) << where;
  EXPECT_EQ(cpu.ee_yes, gpu.ee_yes) << where;
  EXPECT_EQ(cpu.ee_no, gpu.ee_no) << where;
  EXPECT_EQ(cpu.ee_uncertain, gpu.ee_uncertain) << where;
  EXPECT_EQ(cpu.certified, gpu.certified) << where;
  EXPECT_EQ(cpu.certified_true, gpu.certified_true) << where;
  EXPECT_EQ(cpu.triangle_tests, gpu.triangle_tests) << where;
  EXPECT_EQ(cpu.triangles_intersecting, gpu.triangles_intersecting) << where;
  EXPECT_EQ(cpu.predicate_calls, gpu.predicate_calls) << where;
  EXPECT_EQ(cpu.predicate_exact, gpu.predicate_exact) << where;
}

}  // namespace snag::test
