// snag-verify: re-checks a scan report, or a cache scanned on the spot, with
// exact arithmetic, and evaluates CCD methods on query sets with exact ground
// truth.
#include "snag/config.hpp"

#if SNAG_HAVE_CGAL
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "io/ccd_query_csv.hpp"
#include "libcd/core/error.hpp"
#include "libcd/pipeline/scan.hpp"
#include "report/report_reader.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/run_tool.hpp"
#include "tools/common/verify_report.hpp"
#include "validate/exact_certifier.hpp"
#include "validate/verify_events.hpp"
#include "validate/verify_queries.hpp"

namespace {

struct VerifyOptions {
  bool scan = false;
  std::string queries;
  bool exhaustive = false;
  bool json = false;
  double toi_tolerance = 1e-9;
  // --scan only
  std::string mode = "all";
  double thickness = 0;
  double lambda = snag::kDefaultLambda;
  unsigned threads = 0;
};

int run_queries(const VerifyOptions& options) {
  const std::vector<snag::io::CcdQuery> queries = snag::io::read_ccd_query_tree(options.queries);
  if (queries.empty()) {
    throw snag::UsageError("--queries " + options.queries +
                           ": no query files (*.csv in vertex-face/ or edge-edge/ folders)");
  }
  const snag::validate::QueryEvaluation evaluation = snag::validate::evaluate_ccd_queries(queries);
  if (options.json) {
    std::cout << snag::tools::query_evaluation_json(evaluation).dump(1) << "\n";
  } else {
    snag::tools::print_query_evaluation(stdout, evaluation);
  }
  const auto& vf = evaluation.exact_vf;
  const auto& ee = evaluation.exact_ee;
  const bool exact_agrees =
      vf.false_positives + vf.false_negatives + ee.false_positives + ee.false_negatives == 0;
  return exact_agrees ? snag::tools::kExitClean : snag::tools::kExitFound;
}

// The scan's settings that verification must repeat, from the report's header.
void apply_report_settings(const snag::report::ReportReader& reader, snag::tools::CacheArguments& cache,
                           snag::validate::VerifySettings& settings) {
  const snag::report::Header& header = reader.header();
  const std::string& frames = header.settings.frames;
  if (cache.frames.empty()) {
    cache.frames = frames;
  } else if (!frames.empty() && cache.frames != frames) {
    throw snag::UsageError("--frames " + cache.frames + " differs from the report's selection " + frames +
                           "; give the same selection, or none to use the report's");
  }
  if (cache.weld.empty()) cache.weld = header.settings.weld;
  settings.collisions = header.settings.mode != "dcd";
  settings.intersections = header.settings.mode != "ccd";
  // Each object's thickness, a pair's the mean of its two objects'.
  settings.thickness = 0;
  for (const snag::report::ObjectInfo& object : header.objects) {
    settings.object_thickness.push_back(object.thickness);
    settings.thickness = std::max(settings.thickness, object.thickness);
  }
}

int run_verification(snag::tools::CacheArguments cache, const VerifyOptions& options) {
  snag::validate::VerifySettings settings;
  settings.exhaustive = options.exhaustive;
  settings.toi_tolerance = options.toi_tolerance;
  std::unique_ptr<snag::report::ReportReader> reader;
  if (!options.scan) {
    if (cache.inputs.size() < 2) throw snag::UsageError("give a report and its cache: snag-verify REPORT CACHE...");
    reader = std::make_unique<snag::report::ReportReader>(cache.inputs.front());
    cache.inputs.erase(cache.inputs.begin());
    apply_report_settings(*reader, cache, settings);
  } else {
    settings.thickness = options.thickness;
    settings.collisions = options.mode != "dcd";
    settings.intersections = options.mode != "ccd";
  }

  auto source = snag::io::open_cache(snag::tools::to_cache_options(cache));
  std::vector<snag::Event> scanned;
  std::optional<snag::tools::ReportEvents> listed;
  if (reader) {
    listed = snag::tools::read_report_events(*reader, *source);
  } else {
    // A certified CPU scan, as snag-scan --precision certified runs it.
    auto backend = snag::make_cpu_backend();
    auto certifier = snag::validate::make_exact_certifier();
    snag::BackendSettings backend_settings;
    backend_settings.lambda = options.lambda;
    backend_settings.thickness = options.thickness;
    backend_settings.threads = options.threads;
    backend_settings.certifier = certifier.get();
    backend->bind(source->scene(), backend_settings);
    snag::ScanSettings scan;
    scan.collisions = settings.collisions;
    scan.intersections = settings.intersections;
    scanned = snag::scan_cache(*source, *backend, scan).events;
  }
  const std::vector<snag::Event>& events = listed ? listed->events : scanned;

  const snag::validate::VerifyResult result = snag::validate::verify_events(*source, events, settings);
  std::optional<snag::tools::UnlistedEvents> unlisted;
  if (listed && options.exhaustive) {
    unlisted = snag::tools::split_unlisted(reader->header(), *source, *listed, result);
  }
  snag::tools::Verification verification;
  verification.events = &events;
  verification.report = listed ? &*listed : nullptr;
  verification.unlisted = unlisted ? &*unlisted : nullptr;
  verification.result = &result;
  verification.settings = &settings;
  if (options.json) {
    std::cout << snag::tools::verification_json(*source, verification).dump(1) << "\n";
  } else {
    snag::tools::print_verification(stdout, *source, verification);
  }
  return snag::tools::all_confirmed(verification) ? snag::tools::kExitClean : snag::tools::kExitFound;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-verify: re-check a scan report (or a cache) with exact arithmetic, or evaluate CCD on "
               "query sets with exact ground truth.\n"
               "  snag-verify REPORT CACHE...    snag-verify --scan CACHE...    snag-verify --queries DIR"};
  snag::tools::CacheArguments cache;
  VerifyOptions options;
  snag::tools::add_cache_options(app, cache);
  app.get_option("inputs")->required(false)->description(
      "The report (unless --scan), then the cache inputs as for snag-scan: mesh files, patterns, globs,\n"
      "directories, point caches (.pc2, .mdd; with --topology) or animated files");
  app.add_flag("--scan", options.scan, "Scan the cache (CPU, certified) and verify that scan; no report");
  app.add_option("--queries", options.queries,
                 "Evaluate the exact method and the floating-point filter on a CCD query folder or tree");
  app.add_flag("--exhaustive", options.exhaustive,
               "Also decide every pair of the complete (box-filtered) candidate sets exactly, to find misses");
  app.add_flag("--json", options.json, "Write the results as JSON on standard output");
  app.add_option("--toi-tolerance", options.toi_tolerance,
                 "Slack, in frames, allowed between a reported and the exact time-of-impact interval")
      ->check(CLI::NonNegativeNumber);
  app.add_option("-m,--mode", options.mode, "--scan: ccd, dcd or all")->check(CLI::IsMember({"ccd", "dcd", "all"}));
  app.add_option("--thickness", options.thickness, "--scan: contact distance, scene units")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--lambda", options.lambda, "--scan: cell-size coefficient")->check(CLI::Range(1.0001, 100.0));
  app.add_option("-j,--threads", options.threads, "Threads for the scan and the exact checks (0 = all cores)");
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;

  return snag::tools::run_tool("snag-verify", [&] {
    std::unique_ptr<tbb::global_control> thread_limit;
    if (options.threads > 0) {
      thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                           options.threads);
    }
    if (!options.queries.empty()) {
      if (options.scan || !cache.inputs.empty()) throw snag::UsageError("--queries takes no report or cache");
      return run_queries(options);
    }
    if (cache.inputs.empty()) throw snag::UsageError("nothing to verify: give REPORT CACHE..., --scan CACHE... "
                                                     "or --queries DIR (see --help)");
    return run_verification(cache, options);
  });
}

#else  // !SNAG_HAVE_CGAL

#include <cstdio>

int main() {
  std::fprintf(stderr, "snag-verify: error: exact verification needs CGAL; configure with -DSNAG_WITH_CGAL=ON\n");
  return 2;
}

#endif
