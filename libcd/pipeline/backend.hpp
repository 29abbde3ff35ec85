// A back end runs the whole pipeline for one step (collisions) or one frame
// (intersections): broad phase, then narrow phase, then — when a certifier is
// given — exact certification of what floating point could not decide.
// cpu/cpu_backend.cpp and cuda/cuda_backend.cu implement it.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/pipeline/event.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

/// The exact answer for one CCD query (see validate/certifier.hpp).
struct ExactAnswer {
  bool collides = false;
  double toi_lo = 0, toi_hi = 1;  ///< encloses the exact earliest time of impact when collides
};

/// Decides CCD queries exactly. Implemented with CGAL in validate/; libcd only
/// sees this interface. Must be safe to call from several threads at once.
class Certifier {
 public:
  virtual ~Certifier() = default;
  /// points: v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1.
  virtual ExactAnswer vertex_face(const std::array<Vec3, 8>& points, double thickness) const = 0;
  /// points: ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1.
  virtual ExactAnswer edge_edge(const std::array<Vec3, 8>& points, double thickness) const = 0;
};

struct BackendSettings {
  double lambda = kDefaultLambda;  ///< cell size = 3·λ·r_avg
  double thickness = 0;    ///< contact distance, scene units
  unsigned threads = 0;    ///< CPU threads, 0 = all cores
  /// CUDA back end: the most device memory its buffers may hold, bytes (0 =
  /// what the device has free at bind() less a margin). Larger scenes run in
  /// chunks with the same events; one too large for any chunk fails with
  /// UsageError. The CPU back end ignores it.
  std::size_t device_memory_bytes = 0;
  CcdSettings ccd;         ///< the floating-point filter's tuning (thickness is taken from above)
  /// Exact certification of uncertain CCD answers; null = report them as
  /// uncertain (fast mode). Not owned.
  const Certifier* certifier = nullptr;
};

/// Narrow-phase counts: what each test answered.
struct NarrowPhaseStats {
  std::size_t vf_tests = 0, vf_yes = 0, vf_no = 0, vf_uncertain = 0;
  std::size_t ee_tests = 0, ee_yes = 0, ee_no = 0, ee_uncertain = 0;
  std::size_t certified = 0;       ///< uncertain answers decided exactly
  std::size_t certified_true = 0;  ///< of those, real collisions
  std::size_t triangle_tests = 0, triangles_intersecting = 0;
  unsigned long long predicate_calls = 0, predicate_exact = 0;  ///< orientation predicates, and exact fallbacks
  double seconds_ccd = 0, seconds_certify = 0, seconds_static = 0;
  /// Of seconds_ccd and seconds_static: the events' host part (the CPU back
  /// end builds them; the CUDA back end settles and copies those the device
  /// built, certification not included), and the device's part (CUDA
  /// events; 0 on the CPU).
  double seconds_ccd_events = 0, seconds_static_events = 0;
  double seconds_ccd_device = 0, seconds_static_device = 0;
};

/// Counts of a scan or of one step/frame: the broad phases of both kinds and
/// the narrow phase.
struct PipelineStats {
  std::size_t steps = 0, frames = 0;
  BroadPhaseStats ccd_broad;     ///< summed over steps (levels: the most in any step)
  BroadPhaseStats static_broad;  ///< summed over frames
  NarrowPhaseStats narrow;
  void add(const PipelineStats& other);
};

class Backend {
 public:
  virtual ~Backend() = default;
  /// "cpu" or "cuda".
  virtual std::string name() const = 0;
  /// Binds the scene's topology and the settings (topology is uploaded once).
  virtual void bind(const Scene& scene, const BackendSettings& settings) = 0;
  /// Collisions of the step x_t0 -> x_t1 (#V global positions each), appended
  /// to `events` with frame = 0 (the caller sets it) in event_order.
  virtual void collisions(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<Event>& events) = 0;
  /// Intersections of one frame, appended to `events` (frame = 0) in event_order.
  virtual void intersections(const std::vector<Vec3>& x, std::vector<Event>& events) = 0;
  /// Says that positions x (#V) will be passed to a later call, so that a
  /// back end can start moving them to where it computes while it works on
  /// the current frame (the CUDA back end uploads them on a copy stream). x
  /// must stay unchanged until that call. When x was prepared after the x_t1
  /// of a collisions() call, a back end may start the collisions of x_t1 ->
  /// x during that call (the CUDA back end does, on its device, while the
  /// host works on the call's events); a next call for another step only
  /// drops that work. The CPU back end ignores it.
  virtual void prepare(const std::vector<Vec3>& /*x*/) {}
  /// Counts of the last call.
  virtual const PipelineStats& stats() const = 0;
};

/// The multi-threaded CPU back end (always available).
std::unique_ptr<Backend> make_cpu_backend();

}  // namespace snag
