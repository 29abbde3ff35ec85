// snag-report: turns scan reports into what each reader wants: an HTML page,
// a JUnit file for CI servers, CSV for scripts, a Markdown summary, and
// meshes with the faces of each region marked. With no output named it
// prints each report's summary.
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "exporters/csv.hpp"
#include "exporters/digest.hpp"
#include "exporters/frame_positions.hpp"
#include "exporters/html.hpp"
#include "exporters/junit.hpp"
#include "exporters/markdown.hpp"
#include "exporters/marked_ply.hpp"
#include "libcd/core/error.hpp"
#include "report/summary.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/path_list.hpp"
#include "tools/common/replacing_file.hpp"
#include "tools/common/run_tool.hpp"

namespace {

namespace ex = snag::exporters;

struct ReportOptions {
  std::vector<std::string> reports;
  std::string list;        // --list FILE: more reports, one path a line
  std::string html, junit, csv, markdown, marked_meshes;
  std::string junit_granularity = "pair";
  std::string csv_rows = "regions";
  std::string frames;      // --frames LIST: cache frame indices to draw and mark
  std::size_t worst = 3;   // otherwise the N worst frames of each report
  bool quiet = false;
};

// Cache frame indices from "24,25,30:33,40:60:10" (inclusive ranges, optional step).
std::set<std::size_t> parse_frame_list(const std::string& text) {
  std::set<std::size_t> frames;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty()) throw snag::UsageError("--frames " + text + ": an empty item (give N, A:B or A:B:STEP, comma-separated)");
    snag::io::FrameSelection range;
    if (item.find(':') == std::string::npos) {
      range = snag::io::parse_frame_selection(item + ":" + item);
    } else {
      range = snag::io::parse_frame_selection(item);
    }
    if (range.last == static_cast<std::size_t>(-1)) {
      throw snag::UsageError("--frames " + text + ": '" + item + "' has no end (give A:B)");
    }
    for (std::size_t f = range.first; f <= range.last; f += range.step) frames.insert(f);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return frames;
}

// Writes one output: "-" is standard output, anything else a file that
// replaces its destination only when complete.
void write_output(const std::string& path, const std::function<void(std::ostream&)>& write) {
  if (path == "-") {
    write(std::cout);
    std::cout.flush();
    if (!std::cout) throw snag::UsageError("cannot write to standard output");
    return;
  }
  snag::tools::ReplacingFile file(path);
  write(file.stream());
  file.commit();
}

bool has_cache(const snag::tools::CacheArguments& cache) { return !cache.inputs.empty(); }

// The frames each report's 3D view and marked meshes draw: --frames (those
// the report scanned) or its worst frames, most events first.
std::vector<std::vector<std::size_t>> frames_to_draw(const std::vector<ex::ReportDigest>& digests,
                                                     const ReportOptions& options) {
  std::vector<std::vector<std::size_t>> chosen;
  if (options.frames.empty()) {
    for (const ex::ReportDigest& digest : digests) chosen.push_back(ex::worst_frames(digest, options.worst));
    return chosen;
  }
  const std::set<std::size_t> asked = parse_frame_list(options.frames);
  std::set<std::size_t> scanned_by_some;
  for (const ex::ReportDigest& digest : digests) {
    std::vector<std::size_t> frames;
    for (const snag::report::FrameRecord& f : digest.frames) {
      if (asked.count(f.index) > 0) frames.push_back(f.index);
    }
    scanned_by_some.insert(frames.begin(), frames.end());
    chosen.push_back(std::move(frames));
  }
  for (std::size_t f : asked) {
    if (scanned_by_some.count(f) == 0) {
      throw snag::UsageError("--frames: frame " + std::to_string(f) + " was not scanned by " +
                             (digests.size() == 1 ? digests.front().path : "any of the reports"));
    }
  }
  return chosen;
}

void write_marked_meshes(const std::vector<ex::ReportDigest>& digests,
                         const std::vector<std::vector<std::size_t>>& frames,
                         const snag::io::CacheOptions& cache, const std::string& directory) {
  std::map<std::string, std::string> stems;  // file names are made from the reports' stems
  for (const ex::ReportDigest& digest : digests) {
    auto [other, fresh] = stems.emplace(ex::report_stem(digest.path), digest.path);
    if (!fresh) {
      throw snag::UsageError("--marked-meshes: " + other->second + " and " + digest.path +
                             " would write the same file names (" + other->first + "_frame_N.ply): rename one");
    }
    if (digest.header.settings.events == "none") {
      throw snag::UsageError("--marked-meshes: " + digest.path +
                             " was scanned with --events none, so its regions have no face lists to mark");
    }
  }
  for (std::size_t r = 0; r < digests.size(); ++r) {
    if (frames[r].empty()) continue;
    const ex::FramePositions positions(digests[r], cache);
    // Made once the cache is known to be the report's, so that a wrong --cache leaves nothing behind.
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    if (error) throw snag::UsageError("--marked-meshes " + directory + ": " + error.message());
    for (std::size_t frame : frames[r]) {
      const std::vector<std::size_t> regions = ex::face_regions(digests[r], positions.scene(), frame);
      const std::string comment = digests[r].path + " frame " + std::to_string(frame);
      const std::vector<snag::Vec3> x = positions.positions(frame);
      write_output(directory + "/" + ex::marked_mesh_name(digests[r], frame),
                   [&](std::ostream& out) { ex::write_marked_ply(out, positions.scene(), x, regions, comment); });
    }
  }
}

// The 3D view of one report: its meshes and the positions of `frames`.
ex::HtmlScene html_scene(const ex::ReportDigest& digest, const snag::io::CacheOptions& cache,
                         const std::vector<std::size_t>& frames) {
  const ex::FramePositions positions(digest, cache);
  const snag::Scene& scene = positions.scene();
  ex::HtmlScene view;
  for (const snag::Object& object : scene.objects()) {
    ex::HtmlMesh mesh;
    mesh.triangles.assign(object.triangles.begin(), object.triangles.end());
    view.objects.push_back(std::move(mesh));
  }
  for (std::size_t frame : frames) {
    const std::vector<snag::Vec3> x = positions.positions(frame);
    ex::HtmlFrame html_frame;
    html_frame.frame = frame;
    for (std::size_t o = 0; o < scene.objects().size(); ++o) {
      std::vector<float> xyz;
      xyz.reserve(3 * scene.objects()[o].vertex_count);
      for (std::size_t v = scene.vertex_offset(o); v < scene.vertex_offset(o + 1); ++v) {
        xyz.insert(xyz.end(), {static_cast<float>(x[v].x), static_cast<float>(x[v].y), static_cast<float>(x[v].z)});
      }
      html_frame.objects.push_back(std::move(xyz));
    }
    view.frames.push_back(std::move(html_frame));
  }
  return view;
}

// The reports a --list names, after those given as arguments: each must be
// there (a missing one is named with the list's line, before any is read).
std::vector<std::string> listed_reports(const std::string& list) {
  std::vector<std::string> reports;
  for (const snag::tools::ListedPath& listed : snag::tools::read_path_list(list)) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(listed.path, error)) {
      snag::InputLocation where{list};
      where.line = listed.line;
      const bool exists = std::filesystem::exists(listed.path, error);
      throw snag::InputError(where, listed.path + (exists ? ": not a file" : ": no such report"));
    }
    reports.push_back(listed.path);
  }
  if (reports.empty()) throw snag::InputError(snag::InputLocation{list}, "the list names no report");
  return reports;
}

int run(const ReportOptions& options, const snag::tools::CacheArguments& cache_arguments) {
  const bool draws = !options.html.empty() || !options.marked_meshes.empty();
  const bool any_output = draws || !options.junit.empty() || !options.csv.empty() || !options.markdown.empty();
  std::size_t to_stdout = 0;
  for (const std::string* path : {&options.html, &options.junit, &options.csv, &options.markdown}) {
    if (*path == "-") ++to_stdout;
  }
  if (to_stdout > 1) throw snag::UsageError("only one output can go to standard output ('-')");
  if (!options.marked_meshes.empty() && !has_cache(cache_arguments)) {
    throw snag::UsageError("--marked-meshes draws the cache's meshes: give the cache with --cache INPUT "
                           "(and --topology for point caches), as snag-scan was given it");
  }
  if (has_cache(cache_arguments) && !draws) {
    throw snag::UsageError("--cache is read only for --html and --marked-meshes");
  }
  std::optional<snag::io::CacheOptions> cache;
  if (has_cache(cache_arguments)) cache = snag::tools::to_cache_options(cache_arguments);

  std::vector<ex::ReportDigest> digests;
  for (const std::string& path : options.reports) digests.push_back(ex::read_digest(path));
  std::vector<std::vector<std::size_t>> frames;
  if (draws) {
    frames = frames_to_draw(digests, options);
    // Read again, keeping the face lists of the frames drawn.
    for (std::size_t r = 0; r < digests.size(); ++r) {
      if (!frames[r].empty()) {
        digests[r] = ex::read_digest(options.reports[r], std::set<std::size_t>(frames[r].begin(), frames[r].end()));
      }
    }
  }

  if (!options.html.empty()) {
    ex::HtmlInputs inputs;
    for (std::size_t r = 0; r < digests.size() && cache; ++r) {
      if (frames[r].empty()) {
        inputs.scenes.emplace_back();
      } else {
        inputs.scenes.emplace_back(html_scene(digests[r], *cache, frames[r]));
      }
    }
    write_output(options.html, [&](std::ostream& out) { ex::write_html(out, digests, inputs); });
  }
  if (!options.junit.empty()) {
    const ex::JunitGranularity granularity =
        options.junit_granularity == "track" ? ex::JunitGranularity::kTrack : ex::JunitGranularity::kPair;
    write_output(options.junit, [&](std::ostream& out) { ex::write_junit(out, digests, granularity); });
  }
  if (!options.csv.empty()) {
    write_output(options.csv, [&](std::ostream& out) {
      if (options.csv_rows == "events") {
        ex::write_event_csv(out, options.reports);
      } else {
        ex::write_region_csv(out, digests);
      }
    });
  }
  if (!options.markdown.empty()) {
    write_output(options.markdown, [&](std::ostream& out) { ex::write_markdown(out, digests); });
  }
  if (!options.marked_meshes.empty()) write_marked_meshes(digests, frames, *cache, options.marked_meshes);

  // What a person at the terminal reads: the summaries when nothing else was
  // asked for, else a verdict line per report (on standard error when an
  // output took standard output).
  if (!options.quiet) {
    std::FILE* out = to_stdout > 0 ? stderr : stdout;
    for (const ex::ReportDigest& digest : digests) {
      if (any_output) {
        std::fprintf(out, "%s: %s\n", digest.path.c_str(), snag::report::verdict_text(digest.trailer).c_str());
      } else {
        if (digests.size() > 1) std::fprintf(out, "report: %s\n", digest.path.c_str());
        snag::report::print_summary(out, digest.header, digest.trailer);
      }
    }
  }
  bool pass = true;
  for (const ex::ReportDigest& digest : digests) pass = pass && digest.trailer.pass;
  return pass ? snag::tools::kExitClean : snag::tools::kExitFound;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-report: turn scan reports into an HTML page, JUnit XML, CSV, Markdown and meshes with the\n"
               "regions marked; with no output named, print each report's summary.\n"
               "  snag-report [REPORT...] [--list FILE] [--html F] [--junit F] [--csv F] [--markdown F]\n"
               "              [--marked-meshes DIR]\n"
               "              [--cache INPUT [-t MESH]]..."};
  ReportOptions options;
  snag::tools::CacheArguments cache;
  app.add_option("reports", options.reports, "Scan reports (JSON Lines, snag-report(5)); '-' reads standard input")
      ->type_name("REPORT");
  app.add_option("--list", options.list,
                 "Also read the reports FILE names, one a line (relative paths from FILE's directory; blank\n"
                 "lines and '#' comments skipped), as snag-scan --batch's DIR/batch.txt does")
      ->type_name("FILE");
  app.add_option("--html", options.html, "Write the HTML page (one self-contained file; '-' = standard output)")
      ->type_name("FILE");
  app.add_option("--junit", options.junit, "Write JUnit XML, a testsuite per report ('-' = standard output)")
      ->type_name("FILE");
  app.add_option("--junit-granularity", options.junit_granularity,
                 "pair: a testcase per object pair and kind; track: a testcase per track")
      ->check(CLI::IsMember({"pair", "track"}));
  app.add_option("--csv", options.csv, "Write CSV, a row per region or event ('-' = standard output)")
      ->type_name("FILE");
  app.add_option("--csv-rows", options.csv_rows, "regions (default) or events (the events the reports list)")
      ->check(CLI::IsMember({"regions", "events"}));
  app.add_option("--markdown", options.markdown, "Write a Markdown summary ('-' = standard output)")
      ->type_name("FILE");
  app.add_option("--marked-meshes", options.marked_meshes,
                 "Write a PLY per drawn frame into DIR (STEM_frame_N.ply), the faces of each region\n"
                 "coloured; needs --cache")
      ->type_name("DIR");
  app.add_option("--frames", options.frames,
                 "Frames to draw (--html) and mark (--marked-meshes): cache frame indices, N, A:B or A:B:STEP,\n"
                 "comma-separated (default: the --worst frames)")
      ->type_name("LIST");
  app.add_option("--worst", options.worst, "Without --frames: draw and mark each report's N frames with the most events (default 3)")
      ->check(CLI::Range(0, 100000))
      ->type_name("N");
  app.add_option("--cache", cache.inputs,
                 "The report's cache, one input per --cache in the scan's order (a mesh file, pattern, glob,\n"
                 "directory, point cache or animated file); the report's frame selection and weld apply")
      ->type_name("INPUT")
      ->allow_extra_args(false)
      ->take_all();
  app.add_option("-t,--topology", cache.topologies, "Topology mesh of each point cache --cache, in order")
      ->type_name("MESH")
      ->allow_extra_args(false)
      ->take_all();
  app.add_option("-n,--name", cache.names, "Object name of each --cache input, in order (as given to snag-scan)")
      ->type_name("NAME")
      ->allow_extra_args(false)
      ->take_all();
  app.add_flag("-s,--sequence", cache.sequence, "The --cache inputs are the frames of one mesh sequence");
  app.add_option("--fps", cache.sample_rate, "Animated files: samples per second, as given to snag-scan")
      ->check(CLI::PositiveNumber);
  app.add_option("--start", cache.start_time, "Animated files: first sample time in seconds, as given to snag-scan")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--end", cache.end_time, "Animated files: last sample time in seconds, as given to snag-scan")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("-q,--quiet", options.quiet, "Print nothing but errors");
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;

  return snag::tools::run_tool("snag-report", [&] {
    if (app.count("--junit-granularity") > 0 && options.junit.empty()) {
      throw snag::UsageError("--junit-granularity needs --junit");
    }
    if (app.count("--csv-rows") > 0 && options.csv.empty()) throw snag::UsageError("--csv-rows needs --csv");
    if ((app.count("--frames") > 0 || app.count("--worst") > 0) && options.html.empty() &&
        options.marked_meshes.empty()) {
      throw snag::UsageError("--frames and --worst choose the frames of --html and --marked-meshes");
    }
    if (cache.inputs.empty() && (!cache.topologies.empty() || !cache.names.empty() || cache.sequence ||
                                 cache.sample_rate > 0 || cache.start_time >= 0 || cache.end_time >= 0)) {
      throw snag::UsageError("--topology, --name, --sequence, --fps, --start and --end describe a --cache input");
    }
    if (!options.list.empty()) {
      const std::vector<std::string> listed = listed_reports(options.list);
      options.reports.insert(options.reports.end(), listed.begin(), listed.end());
    }
    if (options.reports.empty()) throw snag::UsageError("give the reports: REPORT... or --list FILE");
    std::size_t from_stdin = 0;
    for (const std::string& path : options.reports) from_stdin += path == "-";
    if (from_stdin > 0 && (options.reports.size() > 1 || options.csv_rows == "events" ||
                           !options.html.empty() || !options.marked_meshes.empty())) {
      throw snag::UsageError("a report on standard input ('-') is read once: give it alone, and not with "
                             "--csv-rows events, --html or --marked-meshes (which read it again)");
    }
    return run(options, cache);
  });
}
