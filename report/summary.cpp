#include "report/summary.hpp"

#include <algorithm>

namespace snag::report {

namespace {

std::string pair_name(const Header& header, std::size_t a, std::size_t b) {
  auto name = [&](std::size_t o) { return o < header.objects.size() ? header.objects[o].name : std::string("?"); };
  return a == b ? name(a) + " (self)" : name(a) + " / " + name(b);
}

std::string frames_text(const TrackRecord& t) {
  if (t.first_frame == t.last_frame) return "frame " + std::to_string(t.first_frame);
  return "frames " + std::to_string(t.first_frame) + "-" + std::to_string(t.last_frame);
}

}  // namespace

std::string verdict_text(const Trailer& trailer) {
  if (trailer.pass) return "pass";
  std::string text = "FAIL:";
  for (std::size_t i = 0; i < trailer.failed.size(); ++i) {
    const FailedRule& f = trailer.failed[i];
    text += (i ? ", " : " ") + f.what + " " + std::to_string(f.count) + " >= " + std::to_string(f.threshold);
  }
  return text;
}

void print_summary(std::FILE* out, const Header& header, const Trailer& trailer) {
  std::fprintf(out, "%zu frames, %zu objects; %zu events (%zu collisions, %zu intersections), %zu regions, %zu tracks\n",
               trailer.frames, header.objects.size(), trailer.events, trailer.collisions, trailer.intersections,
               trailer.regions, trailer.tracks);
  if (!trailer.pairs.empty()) {
    std::size_t width = 4;
    for (const PairSummary& p : trailer.pairs) width = std::max(width, pair_name(header, p.object_a, p.object_b).size());
    std::fprintf(out, "  %-*s  %-12s %9s %8s %7s %7s  %s\n", static_cast<int>(width), "pair", "kind", "events",
                 "regions", "tracks", "frames", "worst frame");
    for (const PairSummary& p : trailer.pairs) {
      std::string worst = "-";
      if (p.events > 0) {
        worst = std::to_string(p.worst_frame) + " (" + std::to_string(p.worst_frame_events) + " events)";
      }
      std::fprintf(out, "  %-*s  %-12s %9zu %8zu %7zu %7zu  %s", static_cast<int>(width),
                   pair_name(header, p.object_a, p.object_b).c_str(), kind_name(p.kind), p.events, p.regions,
                   p.tracks, p.frames, worst.c_str());
      if (p.allowed > 0) std::fprintf(out, "; %zu allowed", p.allowed);
      std::fprintf(out, "\n");
    }
  }
  if (trailer.uncertain > 0) {
    std::fprintf(out, "  %zu collisions are uncertain (fast precision: may be false)\n", trailer.uncertain);
  }
  if (trailer.allowed > 0) {
    std::fprintf(out, "  allowed: %zu events (", trailer.allowed);
    bool first = true;
    for (std::size_t r = 0; r < trailer.allow_counts.size(); ++r) {
      if (trailer.allow_counts[r] == 0) continue;
      std::fprintf(out, "%srule %zu: %zu", first ? "" : ", ", r, trailer.allow_counts[r]);
      first = false;
    }
    std::fprintf(out, ")\n");
  }
  if (trailer.not_checked > 0 || trailer.neighbourhood > 0) {
    std::fprintf(out, "  not checked: %zu events of excluded pairs, %zu within %u rings\n", trailer.not_checked,
                 trailer.neighbourhood, header.rules.neighbourhood);
  }
  if (!trailer.largest_tracks.empty()) {
    std::fprintf(out, "largest tracks:\n");
    for (const TrackRecord& t : trailer.largest_tracks) {
      std::fprintf(out, "  track %zu: %s %s, %s (%zu), %zu events, up to %zu faces (frame %zu), around (%.4g, %.4g, %.4g)",
                   t.id, pair_name(header, t.object_a, t.object_b).c_str(), kind_name(t.kind),
                   frames_text(t).c_str(), t.frames, t.events, t.max_faces, t.worst_frame, t.centroid.x,
                   t.centroid.y, t.centroid.z);
      if (t.kind == EventKind::kCollision) std::fprintf(out, ", first contact at %.4f", t.toi);
      std::fprintf(out, "\n");
    }
  }
  if (trailer.left_out > 0) {
    std::fprintf(out, "  %zu of %zu events listed in the report (--max-events %zu); regions cover all\n",
                 trailer.listed, trailer.listed + trailer.left_out, header.settings.max_events);
  }
  std::fprintf(out, "verdict: %s\n", verdict_text(trailer).c_str());
}

}  // namespace snag::report
