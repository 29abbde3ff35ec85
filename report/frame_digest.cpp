#include "report/frame_digest.hpp"

#include <algorithm>

namespace snag::report {

std::size_t events_to_list(const ReportSettings& settings, std::size_t listed, std::size_t kept) {
  if (settings.events != "all") return 0;
  if (settings.max_events == 0) return kept;
  return std::min(kept, settings.max_events - std::min(settings.max_events, listed));
}

FrameDigester::FrameDigester(const Scene& scene, const RuleSet& rules)
    : scene_(scene), rules_(rules), regions_(scene) {}

void FrameDigester::digest(ScannedFrame& frame, FrameDigest& digest) {
  std::vector<Event>& events = *frame.events;
  FrameRecord& record = digest.record;
  record = FrameRecord{};
  record.position = frame.position;
  record.index = frame.summary.frame;
  record.time = frame.time;
  digest.not_checked = 0;
  digest.neighbourhood = 0;
  digest.allow_counts.assign(rules_.rules().allow.size(), 0);
  in_region_.clear();
  digest.allowed_by.clear();
  in_region_.reserve(events.size());
  digest.allowed_by.reserve(events.size());
  pairs_.clear();
  // The events of a pair come in long runs: the last pair's counts are kept
  // at hand instead of a map look-up per event.
  PairKey last_key{-1, 0, 0};
  PairCounts* last_pair = nullptr;
  // The kept events are moved down in place: nothing is copied while no
  // rule drops any.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    const Disposition d = rules_.classify(e);
    if (d.kind == Disposition::kNotChecked) {
      ++digest.not_checked;
      continue;
    }
    if (d.kind == Disposition::kNeighbourhood) {
      ++digest.neighbourhood;
      continue;
    }
    const auto [a, b] = event_objects(scene_, e);
    const PairKey key{static_cast<int>(e.kind), a, b};
    if (key != last_key) {
      last_key = key;
      auto [it, inserted] = pairs_.try_emplace(key);
      if (inserted) it->second = PairCounts{e.kind, a, b, 0, 0};
      last_pair = &it->second;
    }
    if (kept != i) events[kept] = e;
    ++kept;
    if (d.kind == Disposition::kAllowed) {
      in_region_.push_back(0);
      digest.allowed_by.push_back(d.rule);
      ++record.allowed;
      ++last_pair->allowed;
      ++digest.allow_counts[d.rule];
      continue;
    }
    in_region_.push_back(1);
    digest.allowed_by.push_back(kNone);
    ++last_pair->checked;
    if (e.kind == EventKind::kCollision) {
      ++record.collisions;
      record.vf += e.type == ContactType::kVertexFace;
      record.ee += e.type == ContactType::kEdgeEdge;
      record.uncertain += e.certainty == Certainty::kUncertain;
    } else {
      ++record.intersections;
    }
  }
  events.resize(kept);
  digest.pairs.clear();
  for (const auto& [key, counts] : pairs_) digest.pairs.push_back(counts);

  digest.regions.clear();
  regions_.build(events, in_region_, *frame.x, record.index, digest.regions, digest.region_of);
  record.regions = digest.regions.size();
  digest.kept = kept;
  digest.listable = kept;
  digest.events = events.data();
}

}  // namespace snag::report
