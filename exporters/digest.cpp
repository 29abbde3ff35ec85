#include "exporters/digest.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <tuple>

#include "report/report_reader.hpp"
#include "report/summary.hpp"

namespace snag::exporters {

namespace {

// The larger of two regions for ReportDigest::largest_region: more faces, else the earlier id.
bool larger_region(const report::RegionRecord& x, const report::RegionRecord& y) {
  return x.face_count > y.face_count || (x.face_count == y.face_count && x.id < y.id);
}

}  // namespace

ReportDigest read_digest(const std::string& path, const std::set<std::size_t>& keep_faces_of, bool keep_all_faces) {
  report::ReportReader reader(path);
  ReportDigest digest;
  digest.path = path;
  digest.header = reader.header();
  // Largest region per track id as given to regions; resolved to the root tracks at the end.
  std::map<std::size_t, report::RegionRecord> largest_by_given_track;
  for (;;) {
    const report::ReportReader::Record record = reader.next();
    if (record == report::ReportReader::Record::kEnd) break;
    switch (record) {
      case report::ReportReader::Record::kFrame:
        digest.frames.push_back(reader.frame());
        break;
      case report::ReportReader::Record::kEvent:
        break;
      case report::ReportReader::Record::kRegion: {
        const report::RegionRecord& region = reader.region();
        auto [it, inserted] = largest_by_given_track.try_emplace(region.track, region);
        if (!inserted && larger_region(region, it->second)) it->second = region;
        digest.regions.push_back(region);
        if (!keep_all_faces && keep_faces_of.count(region.frame) == 0) {
          digest.regions.back().faces_a = {};
          digest.regions.back().faces_b = {};
        }
        break;
      }
      case report::ReportReader::Record::kTrack:
        digest.tracks.push_back(reader.track());
        break;
      case report::ReportReader::Record::kTrailer:
        digest.trailer = reader.trailer();
        break;
      case report::ReportReader::Record::kEnd:
        break;
    }
  }
  // Regions come in id order within a frame and frames in order; sorted all the same, counts alongside.
  std::vector<std::size_t> order(digest.regions.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return digest.regions[x].id < digest.regions[y].id; });
  std::vector<report::RegionRecord> regions;
  for (std::size_t i : order) regions.push_back(std::move(digest.regions[i]));
  digest.regions = std::move(regions);

  std::map<std::size_t, std::size_t> merged_into;
  for (const report::TrackRecord& track : digest.tracks) merged_into[track.id] = track.merged_into;
  for (const report::TrackRecord& track : digest.tracks) {
    std::size_t root = track.id;
    // A chain is at most as long as the number of tracks; a longer walk is a cycle in a bad report.
    for (std::size_t steps = 0; steps <= digest.tracks.size(); ++steps) {
      auto next = merged_into.find(root);
      if (next == merged_into.end() || next->second == report::kNone) break;
      root = next->second;
    }
    digest.root_track[track.id] = root;
  }
  for (auto& [given, region] : largest_by_given_track) {
    const std::size_t root = root_track_of(digest, given);
    auto [it, inserted] = digest.largest_region.try_emplace(root, region);
    if (!inserted && larger_region(region, it->second)) it->second = std::move(region);
  }
  return digest;
}

std::vector<std::size_t> worst_frames(const ReportDigest& digest, std::size_t count) {
  std::vector<std::pair<std::size_t, std::size_t>> frames;  // (events, index)
  for (const report::FrameRecord& f : digest.frames) {
    const std::size_t events = f.collisions + f.intersections;
    if (events > 0) frames.emplace_back(events, f.index);
  }
  std::sort(frames.begin(), frames.end(), [](const auto& x, const auto& y) {
    return x.first > y.first || (x.first == y.first && x.second < y.second);
  });
  std::vector<std::size_t> worst;
  for (std::size_t i = 0; i < frames.size() && i < count; ++i) worst.push_back(frames[i].second);
  return worst;
}

std::size_t root_track_of(const ReportDigest& digest, std::size_t track) {
  auto found = digest.root_track.find(track);
  return found == digest.root_track.end() ? track : found->second;
}

std::vector<report::PairSummary> checked_pairs(const ReportDigest& digest) {
  const report::Header& header = digest.header;
  const report::ScanRules& rules = header.rules;
  const std::size_t n = header.objects.size();
  auto named = [&](const std::string& name, std::size_t o) { return header.objects[o].name == name; };
  auto checked = [&](std::size_t a, std::size_t b) {
    if (a == b) {
      return std::none_of(rules.no_self.begin(), rules.no_self.end(),
                          [&](const std::string& name) { return named(name, a); });
    }
    if (rules.pairs.empty()) return true;
    return std::any_of(rules.pairs.begin(), rules.pairs.end(), [&](const auto& p) {
      return (named(p.first, a) && named(p.second, b)) || (named(p.first, b) && named(p.second, a));
    });
  };
  using Key = std::tuple<int, std::size_t, std::size_t>;
  std::map<Key, report::PairSummary> pairs;
  std::vector<EventKind> kinds;
  if (header.settings.mode != "dcd") kinds.push_back(EventKind::kCollision);
  if (header.settings.mode != "ccd") kinds.push_back(EventKind::kIntersection);
  for (EventKind kind : kinds) {
    for (std::size_t a = 0; a < n; ++a) {
      for (std::size_t b = a; b < n; ++b) {
        if (!checked(a, b)) continue;
        report::PairSummary p;
        p.kind = kind;
        p.object_a = a;
        p.object_b = b;
        pairs[Key{static_cast<int>(kind), a, b}] = p;
      }
    }
  }
  for (const report::PairSummary& p : digest.trailer.pairs) {
    pairs[Key{static_cast<int>(p.kind), p.object_a, p.object_b}] = p;
  }
  std::vector<report::PairSummary> list;
  for (const auto& [key, p] : pairs) list.push_back(p);
  return list;
}

bool pair_fails(const report::Trailer& trailer, const report::PairSummary& pair) {
  if (trailer.pass || pair.events == 0) return false;
  const char* own = pair.kind == EventKind::kCollision ? "collisions" : "intersections";
  return std::any_of(trailer.failed.begin(), trailer.failed.end(), [&](const report::FailedRule& rule) {
    return rule.what == "events" || rule.what == "regions" || rule.what == "tracks" || rule.what == own;
  });
}

std::string pair_label(const report::Header& header, std::size_t object_a, std::size_t object_b) {
  auto name = [&](std::size_t o) { return o < header.objects.size() ? header.objects[o].name : std::string("?"); };
  return object_a == object_b ? name(object_a) + " (self)" : name(object_a) + " / " + name(object_b);
}

std::string summary_text(const ReportDigest& digest) {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* text = open_memstream(&buffer, &size);
  if (!text) throw std::runtime_error("open_memstream failed");
  report::print_summary(text, digest.header, digest.trailer);
  std::fclose(text);
  std::string summary(buffer, size);
  std::free(buffer);
  return summary;
}

std::string report_stem(const std::string& path) {
  if (path == "-") return "stdin";
  std::string name = path.substr(path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/') + 1);
  for (const char* extension : {".jsonl", ".json"}) {
    const std::string ext = extension;
    if (name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0) {
      return name.substr(0, name.size() - ext.size());
    }
  }
  return name;
}

}  // namespace snag::exporters
