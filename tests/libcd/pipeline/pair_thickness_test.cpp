// redecide_at_pair_thickness against its oracle: the CPU back end run at each
// pair's own thickness gives exactly the events (ids, toi, position,
// certainty) of one run at the largest pair thickness re-decided per pair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "libcd/pipeline/backend.hpp"
#include "libcd/pipeline/pair_thickness.hpp"
#include "tests/common/event_compare.hpp"
#include "tests/common/grid_object.hpp"

namespace snag {
namespace {

Object grid(const std::string& name, Index n) { return test::grid_object(name, n); }

/// A two-object step: a flat cloth grid at rest (z = 0, a slight ripple), and
/// a body grid above it that sinks and tilts, so that at the end it lies from
/// 0.004 to 0.03 above the cloth: some pairs come within the body's
/// thickness, fewer within the cloth–body mean, and a third object, a sliver
/// triangle, falls through the cloth.
struct Step {
  Scene scene{{grid("cloth", 6), grid("body", 5), make_object("pin", 3, {Triangle{0, 1, 2}})}};
  std::vector<Vec3> x_t0, x_t1;
  Step() {
    const double n_cloth = 5, n_body = 4;
    for (int i = 0; i <= 5; ++i) {
      for (int j = 0; j <= 5; ++j) {
        const Vec3 p{i / n_cloth, j / n_cloth, 0.001 * std::sin(3.0 * i + j)};
        x_t0.push_back(p);
        x_t1.push_back(p);
      }
    }
    for (int i = 0; i <= 4; ++i) {
      for (int j = 0; j <= 4; ++j) {
        const double x = 0.05 + 0.9 * i / n_body, y = 0.05 + 0.9 * j / n_body;
        x_t0.push_back({x, y, 0.2});
        x_t1.push_back({x, y, 0.004 + 0.026 * x});
      }
    }
    x_t0.insert(x_t0.end(), {Vec3{0.31, 0.33, 0.05}, Vec3{0.36, 0.33, 0.05}, Vec3{0.33, 0.37, 0.06}});
    x_t1.insert(x_t1.end(), {Vec3{0.31, 0.33, -0.05}, Vec3{0.36, 0.33, -0.05}, Vec3{0.33, 0.37, -0.04}});
  }
};

std::size_t object_a(const Scene& scene, const Event& e) {
  return e.type == ContactType::kVertexFace ? scene.object_of_vertex(e.a) : scene.object_of_edge(e.a);
}
std::size_t object_b(const Scene& scene, const Event& e) {
  return e.type == ContactType::kVertexFace ? scene.object_of_triangle(e.b) : scene.object_of_edge(e.b);
}

std::vector<Event> run_cpu(const Step& step, double thickness, std::size_t frame, const CcdSettings& ccd = {},
                           const Certifier* certifier = nullptr) {
  auto backend = make_cpu_backend();
  BackendSettings settings;
  settings.thickness = thickness;
  settings.threads = 2;
  settings.ccd = ccd;
  settings.certifier = certifier;
  backend->bind(step.scene, settings);
  std::vector<Event> events;
  backend->collisions(step.x_t0, step.x_t1, events);
  for (Event& e : events) e.frame = frame;
  return events;
}

const std::vector<double> kThickness = {0.002, 0.02, 0.0};  // cloth, body, pin

double pair_thickness(std::size_t a, std::size_t b) { return 0.5 * (kThickness[a] + kThickness[b]); }

/// The oracle: one CPU run per pair thickness, each keeping the events of its pairs.
std::vector<Event> run_at_each_pair_thickness(const Step& step, std::size_t frame, const CcdSettings& ccd,
                                              const Certifier* certifier) {
  std::map<double, int> distinct;
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = a; b < 3; ++b) distinct[pair_thickness(a, b)] = 0;
  }
  std::vector<Event> events;
  for (const auto& [h, unused] : distinct) {
    for (const Event& e : run_cpu(step, h, frame, ccd, certifier)) {
      if (pair_thickness(object_a(step.scene, e), object_b(step.scene, e)) == h) events.push_back(e);
    }
  }
  std::sort(events.begin(), events.end(), event_order);
  return events;
}

double largest_pair_thickness() {
  double most = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = a; b < 3; ++b) most = std::max(most, pair_thickness(a, b));
  }
  return most;
}

TEST(RedecideAtPairThickness, GivesTheEventsOfARunAtEachPairsThickness) {
  const Step step;
  const std::size_t frame = 7;
  const std::vector<Event> want = run_at_each_pair_thickness(step, frame, CcdSettings{}, nullptr);

  const double run_thickness = largest_pair_thickness();
  std::vector<Event> events = run_cpu(step, run_thickness, frame);
  const std::size_t at_max = events.size();
  Event intersection;
  intersection.kind = EventKind::kIntersection;
  intersection.type = ContactType::kTriangleTriangle;
  intersection.frame = frame + 1;
  intersection.a = 0;
  intersection.b = 60;  // a cloth triangle against a body triangle: kept as it is
  events.push_back(intersection);
  const RedecideCounts counts = redecide_at_pair_thickness(step.scene, step.x_t0, step.x_t1, kThickness,
                                                           run_thickness, CcdSettings{}, nullptr, events);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, EventKind::kIntersection);
  events.pop_back();

  test::expect_same_events(want, events, "redecided");
  EXPECT_GT(counts.redecided, 0u);
  EXPECT_GT(counts.removed, 0u) << "the step must have pairs that touch at the largest thickness only";
  EXPECT_EQ(at_max - counts.removed, want.size());
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> per_pair;
  for (const Event& e : want) {
    std::size_t a = object_a(step.scene, e), b = object_b(step.scene, e);
    ++per_pair[{std::min(a, b), std::max(a, b)}];
  }
  EXPECT_GT((per_pair[{0, 1}]), 0u) << "cloth–body contacts at their mean thickness";
  EXPECT_GT((per_pair[{0, 2}]), 0u) << "the pin falls through the cloth";
}

TEST(RedecideAtPairThickness, LeavesEventsAtTheRunThicknessUntouched) {
  const Step step;
  const std::vector<double> thickness = {0.01, 0.01, 0.01};  // every pair at the run's thickness
  std::vector<Event> events = run_cpu(step, 0.01, 3);
  const std::vector<Event> before = events;
  ASSERT_FALSE(events.empty());
  const RedecideCounts counts =
      redecide_at_pair_thickness(step.scene, step.x_t0, step.x_t1, thickness, 0.01, CcdSettings{}, nullptr, events);
  EXPECT_EQ(counts.redecided, 0u);
  test::expect_same_events(before, events, "redecided");
}

/// A certifier that answers every query "collides, toi in [0.25, 0.5]" and
/// records the thicknesses it was asked at (it is called from several threads).
class FixedCertifier final : public Certifier {
 public:
  ExactAnswer vertex_face(const std::array<Vec3, 8>&, double thickness) const override { return answer(thickness); }
  ExactAnswer edge_edge(const std::array<Vec3, 8>&, double thickness) const override { return answer(thickness); }
  std::vector<double> thicknesses() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return thicknesses_;
  }

 private:
  ExactAnswer answer(double thickness) const {
    std::lock_guard<std::mutex> lock(mutex_);
    thicknesses_.push_back(thickness);
    return {true, 0.25, 0.5};
  }
  mutable std::mutex mutex_;
  mutable std::vector<double> thicknesses_;
};

TEST(RedecideAtPairThickness, CertifiesUncertainAnswersAtThePairsThickness) {
  const Step step;
  // A filter that gives up at once: what the early exits and the decisions by
  // structure leave is uncertain and goes to the certifier.
  CcdSettings ccd;
  ccd.max_iterations = 1;
  ccd.time_tolerance = 0.5;
  FixedCertifier oracle_certifier;
  const std::vector<Event> want = run_at_each_pair_thickness(step, 0, ccd, &oracle_certifier);

  const double run_thickness = largest_pair_thickness();
  FixedCertifier certifier;
  std::vector<Event> events = run_cpu(step, run_thickness, 0, ccd, &certifier);
  const std::size_t calls_at_max = certifier.thicknesses().size();
  redecide_at_pair_thickness(step.scene, step.x_t0, step.x_t1, kThickness, run_thickness, ccd, &certifier, events);
  test::expect_same_events(want, events, "redecided");
  EXPECT_TRUE(std::any_of(want.begin(), want.end(), [](const Event& e) { return e.toi_lo == 0.25; }))
      << "some events must be the certifier's";

  const std::vector<double> asked = certifier.thicknesses();
  ASSERT_GT(asked.size(), calls_at_max) << "the re-decision must meet uncertain answers";
  for (std::size_t k = calls_at_max; k < asked.size(); ++k) {
    const double h = asked[k];
    EXPECT_TRUE(h == pair_thickness(0, 0) || h == pair_thickness(0, 1) || h == pair_thickness(0, 2) ||
                h == pair_thickness(1, 2) || h == pair_thickness(2, 2))
        << h;
  }
}

}  // namespace
}  // namespace snag
