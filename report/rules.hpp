// The rules a scan is judged by, kept in a scene manifest (man/snag-manifest.5)
// or given on the command line: which object pairs are checked (collision
// groups, self-collision per object), the contact thickness per object, a
// neighbourhood exclusion, an allow-list of known contacts, and the fail
// thresholds. The scan's events pass through a RuleSet before regions are
// built: each is checked, allowed by a rule (counted, listed, never failing
// the scan), or not checked (dropped, counted by reason).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "libcd/pipeline/event.hpp"
#include "libcd/scene/scene.hpp"

namespace snag::report {

/// A known contact that does not fail the scan. Empty object names match any
/// object; the pair matches in either order.
struct AllowRule {
  std::string object_a, object_b;
  std::optional<EventKind> kind;               ///< unset: both kinds
  std::size_t first_frame = 0;                 ///< cache frame indices, inclusive
  std::size_t last_frame = static_cast<std::size_t>(-1);
  std::optional<std::array<Vec3, 2>> box;      ///< lo, hi: the event's position must lie inside (closed)
  std::string note;                            ///< why it is allowed, for the report
};

/// Fail thresholds: the scan fails when a count reaches its threshold;
/// 0 = never. Counts are of checked events (allowed and not-checked ones
/// excluded), regions and tracks.
struct FailThresholds {
  std::size_t events = 1;
  std::size_t collisions = 0, intersections = 0, regions = 0, tracks = 0;
};

/// Rules as written (names, not ids); RuleSet resolves them against a scene.
struct ScanRules {
  /// Thickness per object name; objects not named use the global thickness.
  std::vector<std::pair<std::string, double>> thickness;
  /// Pairs of different objects that are checked against each other; empty:
  /// every pair. Names; order within a pair does not matter.
  std::vector<std::pair<std::string, std::string>> pairs;
  /// Objects whose self-collisions and self-intersections are not checked.
  std::vector<std::string> no_self;
  /// Pairs of one object closer than this many topological rings are not
  /// checked (0: off; pairs sharing a vertex are never pairs anyway). A
  /// vertex–face pair is within k rings when the vertex is at most k edges
  /// from a corner of the face; an edge–edge pair when an end of one is at
  /// most k edges from an end of the other; two faces likewise by corners.
  unsigned neighbourhood = 0;
  std::vector<AllowRule> allow;
  FailThresholds fail;
};

/// What the rules say about one event.
struct Disposition {
  enum Kind { kChecked, kAllowed, kNotChecked, kNeighbourhood } kind = kChecked;
  std::size_t rule = 0;  ///< kAllowed: index into ScanRules::allow (the first that matches)
};

/// The rules resolved against a scene. Throws UsageError naming an object
/// that the scene lacks, or a negative thickness.
/// Every const member, classify() included, may be called from several
/// threads at once. The scene must outlive the RuleSet.
class RuleSet {
 public:
  RuleSet(const Scene& scene, ScanRules rules, double global_thickness);
  const ScanRules& rules() const { return rules_; }
  /// Contact thickness of object o, and of a pair: the mean of the two (so
  /// that every object at h gives h for every pair).
  double object_thickness(std::size_t o) const { return thickness_[o]; }
  double pair_thickness(std::size_t a, std::size_t b) const { return 0.5 * (thickness_[a] + thickness_[b]); }
  /// The largest pair thickness: what the back end must run with.
  double max_thickness() const;
  /// True when some pair's thickness is below max_thickness() (the scan must then re-decide collisions).
  bool thickness_varies() const;
  /// Whether the pair of objects a, b (a may equal b) is checked at all.
  bool pair_checked(std::size_t a, std::size_t b) const;
  /// Disposition of an event of frame `event.frame` (cache index), with global ids.
  Disposition classify(const Event& event) const;

 private:
  /// An allow rule with its object names resolved: which objects each side matches.
  struct ResolvedAllow {
    std::vector<char> side_a, side_b;  ///< #objects flags; empty: any object
  };
  /// Whether the event's two elements (one object) lie within `neighbourhood` rings.
  bool within_rings(const Event& event) const;
  bool allows(const AllowRule& rule, const ResolvedAllow& resolved, std::size_t a, std::size_t b,
              const Event& event) const;

  const Scene* scene_;
  ScanRules rules_;
  std::vector<double> thickness_;
  std::vector<char> checked_;  // objects² matrix
  std::vector<ResolvedAllow> allow_;
  // Vertex adjacency of the scene's edges (CSR), built only when neighbourhood > 0:
  // the neighbours of global vertex v are neighbours_[neighbour_offset_[v] .. neighbour_offset_[v + 1]).
  std::vector<Index> neighbour_offset_, neighbours_;
};

/// One threshold that was reached.
struct FailedRule {
  std::string what;       ///< "events", "collisions", "intersections", "regions" or "tracks"
  std::size_t count = 0, threshold = 0;
};

struct Counts {
  std::size_t events = 0, collisions = 0, intersections = 0, regions = 0, tracks = 0;
};

/// The thresholds reached by `counts`, in the order of FailThresholds' fields.
std::vector<FailedRule> judge(const FailThresholds& fail, const Counts& counts);

}  // namespace snag::report
