#include "report/frame_digest.hpp"

#include <algorithm>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace snag::report {

namespace {

// Events per task of the rules' pass: a task costs more than a few events.
constexpr std::size_t kEventsPerTask = 2048;

}  // namespace

std::size_t events_to_list(const ReportSettings& settings, std::size_t listed, std::size_t kept) {
  if (settings.events != "all") return 0;
  if (settings.max_events == 0) return kept;
  return std::min(kept, settings.max_events - std::min(settings.max_events, listed));
}

FrameDigester::FrameDigester(const Scene& scene, const RuleSet& rules, std::shared_ptr<const FaceAdjacency> faces)
    : scene_(scene), rules_(rules), regions_(scene, std::move(faces)) {}

void FrameDigester::Tally::add(const Tally& other) {
  collisions += other.collisions;
  vf += other.vf;
  ee += other.ee;
  uncertain += other.uncertain;
  intersections += other.intersections;
  allowed += other.allowed;
  not_checked += other.not_checked;
  neighbourhood += other.neighbourhood;
  for (std::size_t rule = 0; rule < allow_counts.size(); ++rule) allow_counts[rule] += other.allow_counts[rule];
  for (const auto& [key, counts] : other.pairs) {
    auto [it, inserted] = pairs.try_emplace(key, counts);
    if (!inserted) {
      it->second.checked += counts.checked;
      it->second.allowed += counts.allowed;
    }
  }
}

// The rules on events [begin, end): their dispositions, the group of each
// checked one (kNoGroup for the others) and the rule that allowed it, at the
// event's own index, and the counts into `sum`.
void FrameDigester::tally(const std::vector<Event>& events, std::size_t begin, std::size_t end,
                          std::vector<std::size_t>& allowed_by, Tally& sum) {
  // The events of a pair come in long runs: the last pair's counts are kept
  // at hand instead of a map look-up per event.
  PairKey last_key{-1, 0, 0};
  PairCounts* last_pair = nullptr;
  for (std::size_t i = begin; i < end; ++i) {
    const Event& e = events[i];
    const Disposition d = rules_.classify(e);
    dispositions_[i] = d.kind;
    group_of_[i] = kNoGroup;
    allowed_by[i] = kNone;
    if (d.kind == Disposition::kNotChecked) {
      ++sum.not_checked;
      continue;
    }
    if (d.kind == Disposition::kNeighbourhood) {
      ++sum.neighbourhood;
      continue;
    }
    const auto [a, b] = event_objects(scene_, e);
    const PairKey key{static_cast<int>(e.kind), a, b};
    if (key != last_key) {
      last_key = key;
      auto [it, inserted] = sum.pairs.try_emplace(key);
      if (inserted) it->second = PairCounts{e.kind, a, b, 0, 0};
      last_pair = &it->second;
    }
    if (d.kind == Disposition::kAllowed) {
      allowed_by[i] = d.rule;
      ++sum.allowed;
      ++last_pair->allowed;
      ++sum.allow_counts[d.rule];
      continue;
    }
    group_of_[i] = group_word(e.kind, a, b);
    ++last_pair->checked;
    if (e.kind == EventKind::kCollision) {
      ++sum.collisions;
      sum.vf += e.type == ContactType::kVertexFace;
      sum.ee += e.type == ContactType::kEdgeEdge;
      sum.uncertain += e.certainty == Certainty::kUncertain;
    } else {
      ++sum.intersections;
    }
  }
}

void FrameDigester::digest(ScannedFrame& frame, FrameDigest& digest) {
  std::vector<Event>& events = *frame.events;
  FrameRecord& record = digest.record;
  record = FrameRecord{};
  record.position = frame.position;
  record.index = frame.summary.frame;
  record.time = frame.time;

  // The rules on all threads (classify may run on several at once), each
  // event's results at its own index; counts summed over the blocks.
  const std::size_t count = events.size();
  dispositions_.resize(count);
  group_of_.resize(count);
  digest.allowed_by.resize(count);
  Tally none;
  none.allow_counts.assign(rules_.rules().allow.size(), 0);
  Tally total = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count, kEventsPerTask), none,
      [&](const tbb::blocked_range<std::size_t>& range, Tally sum) {
        tally(events, range.begin(), range.end(), digest.allowed_by, sum);
        return sum;
      },
      [](Tally left, const Tally& right) {
        left.add(right);
        return left;
      });
  record.collisions = total.collisions;
  record.vf = total.vf;
  record.ee = total.ee;
  record.uncertain = total.uncertain;
  record.intersections = total.intersections;
  record.allowed = total.allowed;
  digest.not_checked = total.not_checked;
  digest.neighbourhood = total.neighbourhood;
  digest.allow_counts = std::move(total.allow_counts);
  digest.pairs.clear();
  for (const auto& [key, counts] : total.pairs) digest.pairs.push_back(counts);

  // The events the rules dropped leave the list, the kept ones moved down in
  // place in order (nothing moves while no rule drops any).
  std::size_t kept = count;
  if (total.not_checked + total.neighbourhood > 0) {
    kept = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (dispositions_[i] == Disposition::kNotChecked || dispositions_[i] == Disposition::kNeighbourhood) continue;
      if (kept != i) {
        events[kept] = events[i];
        group_of_[kept] = group_of_[i];
        digest.allowed_by[kept] = digest.allowed_by[i];
      }
      ++kept;
    }
    events.resize(kept);
    group_of_.resize(kept);
    digest.allowed_by.resize(kept);
  }

  digest.regions.clear();
  regions_.build(events, group_of_, *frame.x, record.index, digest.regions, digest.region_of);
  record.regions = digest.regions.size();
  digest.kept = kept;
  digest.listable = kept;
  digest.events = events.data();
}

}  // namespace snag::report
