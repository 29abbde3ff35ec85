// snag-scan: finds every collision between consecutive frames (CCD) and every
// intersection within a frame (DCD) of a cache, joins them into regions and
// tracks, judges them by the rules, streams the report and prints a summary.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <set>

#include "libcd/core/error.hpp"
#include "libcd/pipeline/pair_thickness.hpp"
#include "libcd/pipeline/scan.hpp"
#include "report/report_sink.hpp"
#include "report/summary.hpp"
#include "snag/config.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/replacing_file.hpp"
#include "tools/common/rule_options.hpp"
#include "tools/common/run_tool.hpp"
#include "tools/common/scan_stats.hpp"
#if SNAG_HAVE_CGAL
#include "validate/exact_certifier.hpp"
#endif
#if SNAG_HAVE_CUDA
#include "libcd/cuda/cuda_backend.hpp"
#include "libcd/cuda/device.hpp"
#endif

namespace {

struct ScanOptions {
  std::string mode = "all";
  double thickness = 0;
  std::string backend = "auto";
  unsigned threads = 0;
  double lambda = 1.2;
  std::string report;
  std::string events = "all";
  std::size_t max_events = 100000;
  bool json = false;
  bool quiet = false;
  std::string precision = "certified";
};

// auto: the CUDA back end when this build has it and a usable device is
// present, else the CPU one. cuda: the CUDA back end or a usage error (exit 2)
// saying why it cannot run.
std::unique_ptr<snag::Backend> choose_backend(const std::string& requested) {
  if (requested == "cpu") return snag::make_cpu_backend();
#if SNAG_HAVE_CUDA
  const snag::CudaDeviceInfo device = snag::query_cuda_device();
  if (device.available) return snag::make_cuda_backend();
  if (requested == "cuda") throw snag::UsageError("--backend cuda: " + device.why_not);
#else
  if (requested == "cuda") {
    throw snag::UsageError("--backend cuda: this build has no CUDA back end: configure with -DSNAG_WITH_CUDA=ON");
  }
#endif
  return snag::make_cpu_backend();
}

// Reports name objects; two objects of one name could not be told apart.
void check_object_names(const snag::Scene& scene) {
  std::set<std::string> names;
  for (const snag::Object& object : scene.objects()) {
    if (!names.insert(object.name).second) {
      throw snag::UsageError("two objects are named '" + object.name + "': give each input a --name");
    }
  }
}

snag::report::Header make_header(const snag::FrameSource& source, const snag::report::RuleSet& rules,
                                 const snag::tools::ScanSetup& setup, const ScanOptions& options,
                                 const std::string& backend) {
  snag::report::Header header;
  header.snag_version = SNAG_VERSION;
  header.source = source.description();
  const snag::Scene& scene = source.scene();
  for (std::size_t o = 0; o < scene.objects().size(); ++o) {
    const snag::Object& object = scene.objects()[o];
    header.objects.push_back({object.name, object.vertex_count, snag::file_vertex_count(object),
                              object.triangles.size(), object.edges.size(), object.weld.method,
                              rules.object_thickness(o)});
  }
  header.frame_count = source.frame_count();
  snag::report::ReportSettings& s = header.settings;
  s.mode = options.mode;
  s.backend = backend;
  s.precision = options.precision;
  s.thickness = setup.thickness;
  s.lambda = options.lambda;
  s.threads = options.threads;
  s.frames = setup.frames;
  s.weld = setup.weld;
  s.events = options.events;
  s.max_events = options.max_events;
  s.manifest = setup.manifest;
  header.rules = rules.rules();
  header.certified = options.precision == "certified";
  return header;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-scan: find collisions between frames and intersections within frames of a mesh cache"};
  snag::tools::CacheArguments cache;
  snag::tools::RuleArguments rule_arguments;
  ScanOptions options;
  snag::tools::add_cache_options(app, cache);
  snag::tools::add_rule_options(app, rule_arguments);
  app.add_option("-m,--mode", options.mode, "ccd (collisions between frames), dcd (intersections in frames), or all")
      ->check(CLI::IsMember({"ccd", "dcd", "all"}));
  app.add_option("--thickness", options.thickness,
                 "Contact distance for collisions, in scene units (objects without their own thickness)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("-b,--backend", options.backend, "auto, cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  app.add_option("-j,--threads", options.threads, "CPU threads (0 = all cores)");
  app.add_option("--lambda", options.lambda, "Cell-size coefficient: cell = 3 x lambda x mean triangle radius")
      ->check(CLI::Range(1.0001, 100.0));
  app.add_option("-r,--report", options.report,
                 "Write the report (JSON Lines, man snag-report(5)) to FILE ('-' = standard output)");
  app.add_option("--events", options.events,
                 "What the report lists besides regions and tracks: all (every event, up to --max-events),\n"
                 "regions (no events), or none (no events, and regions without their face lists)")
      ->check(CLI::IsMember({"all", "regions", "none"}));
  app.add_option("--max-events", options.max_events,
                 "With --events all: list at most N events, counting those left out (0 = no cap)");
  app.add_flag("--json", options.json, "Print the summary as JSON (the report's trailer record) on standard output");
  app.add_option("--precision", options.precision,
                 "certified (uncertain answers decided exactly) or fast (uncertain answers reported as such)")
      ->check(CLI::IsMember({"certified", "fast"}));
  app.add_flag("-q,--quiet", options.quiet, "No summary or progress");
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;

  return snag::tools::run_tool("snag-scan", [&] {
    if (options.json && options.report == "-") {
      throw snag::UsageError("--json and --report - both write to standard output: give the report a file");
    }
    std::optional<double> thickness_option;
    if (app.count("--thickness") > 0) thickness_option = options.thickness;
    const snag::tools::ScanSetup setup = snag::tools::resolve_scan_setup(cache, rule_arguments, thickness_option);
    auto source = snag::io::open_cache(setup.cache);
    const snag::Scene& scene = source->scene();
    check_object_names(scene);
    const snag::report::RuleSet rules(scene, setup.rules, setup.thickness);
    auto backend = choose_backend(options.backend);

    snag::BackendSettings backend_settings;
    backend_settings.lambda = options.lambda;
    backend_settings.thickness = rules.max_thickness();
    backend_settings.threads = options.threads;
#if SNAG_HAVE_CGAL
    std::unique_ptr<snag::Certifier> certifier;
    if (options.precision == "certified") {
      certifier = snag::validate::make_exact_certifier();
      backend_settings.certifier = certifier.get();
    }
#else
    if (options.precision == "certified") {
      throw snag::UsageError("--precision certified needs exact arithmetic, which this build lacks "
                             "(configure with -DSNAG_WITH_CGAL=ON); use --precision fast");
    }
#endif
    backend->bind(scene, backend_settings);

    // Pairs thinner than the run's thickness are decided again at their own.
    snag::report::Redecide redecide;
    if (rules.thickness_varies()) {
      std::vector<double> object_thickness;
      for (std::size_t o = 0; o < scene.objects().size(); ++o) object_thickness.push_back(rules.object_thickness(o));
      redecide = [&scene, object_thickness, &backend_settings](const std::vector<snag::Vec3>& x_t0,
                                                               const std::vector<snag::Vec3>& x_t1,
                                                               std::vector<snag::Event>& events) {
        snag::redecide_at_pair_thickness(scene, x_t0, x_t1, object_thickness, backend_settings.thickness,
                                         backend_settings.ccd, backend_settings.certifier, events);
      };
    }

    snag::ScanSettings scan;
    scan.collisions = options.mode != "dcd";
    scan.intersections = options.mode != "ccd";
    const bool show_progress = !options.quiet && isatty(STDERR_FILENO);
    auto progress = [&](std::size_t done, std::size_t total) {
      if (show_progress) std::fprintf(stderr, "\rsnag-scan: frame %zu of %zu", done, total);
      if (show_progress && done == total) std::fprintf(stderr, "\n");
    };
    // Made before the scan, so that a report that cannot be written fails
    // at once; an earlier report stays untouched until this one is complete.
    std::optional<snag::tools::ReplacingFile> report_file;
    std::unique_ptr<snag::report::ReportWriter> writer;
    if (options.report == "-") {
      writer = std::make_unique<snag::report::ReportWriter>(std::cout);
    } else if (!options.report.empty()) {
      report_file.emplace(options.report);
      writer = std::make_unique<snag::report::ReportWriter>(report_file->stream());
    }
    const snag::report::Header header = make_header(*source, rules, setup, options, backend->name());
    snag::report::ReportSink sink(scene, header, rules, writer.get(), redecide);
    const snag::ScanTotals totals = snag::scan_cache(*source, *backend, scan, sink, progress);
    const snag::report::Trailer& trailer =
        sink.finish(snag::tools::stages_json(totals), snag::tools::timing_json(totals));
    if (report_file) report_file->commit();

    if (options.json) {
      snag::report::ReportWriter json(std::cout);
      json.use_names_of(header);
      json.write_trailer(trailer);
    } else if (!options.quiet) {
      std::FILE* out = options.report == "-" ? stderr : stdout;
      std::fprintf(out, "snag-scan: %s on %s, %.3f s\n", source->description().c_str(), backend->name().c_str(),
                   totals.total_seconds);
      snag::report::print_summary(out, header, trailer);
      if (!options.report.empty() && options.report != "-") std::fprintf(out, "report: %s\n", options.report.c_str());
    }
    return trailer.pass ? snag::tools::kExitClean : snag::tools::kExitFound;
  });
}
