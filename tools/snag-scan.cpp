// snag-scan: finds every collision between consecutive frames (CCD) and every
// intersection within a frame (DCD) of a cache, and writes the report.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "libcd/core/error.hpp"
#include "libcd/pipeline/scan.hpp"
#include "snag/config.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/replacing_file.hpp"
#include "tools/common/report.hpp"
#include "tools/common/run_tool.hpp"
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
  std::string report = "-";
  std::size_t fail_on = 1;
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

void print_summary(const snag::ScanResult& result, const std::string& backend) {
  std::size_t collisions = 0, intersections = 0, uncertain = 0;
  for (const auto& f : result.frames) {
    collisions += f.collisions;
    intersections += f.intersections;
    uncertain += f.uncertain;
  }
  std::fprintf(stderr, "snag-scan: %zu frames, %zu collisions (%zu uncertain), %zu intersections; %.3f s on %s\n",
               result.frames.size(), collisions, uncertain, intersections, result.total_seconds, backend.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-scan: find collisions between frames and intersections within frames of a mesh cache"};
  snag::tools::CacheArguments cache;
  ScanOptions options;
  snag::tools::add_cache_options(app, cache);
  app.add_option("-m,--mode", options.mode, "ccd (collisions between frames), dcd (intersections in frames), or all")
      ->check(CLI::IsMember({"ccd", "dcd", "all"}));
  app.add_option("--thickness", options.thickness, "Contact distance for collisions, in scene units")
      ->check(CLI::NonNegativeNumber);
  app.add_option("-b,--backend", options.backend, "auto, cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  app.add_option("-j,--threads", options.threads, "CPU threads (0 = all cores)");
  app.add_option("--lambda", options.lambda, "Cell-size coefficient: cell = 3 x lambda x mean triangle radius")
      ->check(CLI::Range(1.0001, 100.0));
  app.add_option("-r,--report", options.report, "Write the JSON report to FILE ('-' = standard output)");
  app.add_option("--fail-on", options.fail_on, "Exit 1 when at least N events are found (0 = never)");
  app.add_option("--precision", options.precision,
                 "certified (uncertain answers decided exactly) or fast (uncertain answers reported as such)")
      ->check(CLI::IsMember({"certified", "fast"}));
  app.add_flag("-q,--quiet", options.quiet, "No summary or progress on standard error");
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;

  return snag::tools::run_tool("snag-scan", [&] {
    auto source = snag::io::open_cache(snag::tools::to_cache_options(cache));
    auto backend = choose_backend(options.backend);

    snag::BackendSettings backend_settings;
    backend_settings.lambda = options.lambda;
    backend_settings.thickness = options.thickness;
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
    backend->bind(source->scene(), backend_settings);

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
    if (options.report != "-") report_file.emplace(options.report);
    snag::ScanResult result = snag::scan_cache(*source, *backend, scan, progress);

    snag::tools::ReportSettings report_settings;
    report_settings.mode = options.mode;
    report_settings.backend = backend->name();
    report_settings.precision = options.precision;
    report_settings.thickness = options.thickness;
    report_settings.lambda = options.lambda;
    report_settings.threads = options.threads;
    report_settings.frames = cache.frames;
    report_settings.source = source->description();
    report_settings.weld = cache.weld.empty() ? "auto" : cache.weld;
    const std::string text = snag::tools::make_report(*source, result, report_settings).dump(1) + "\n";
    if (options.report == "-") {
      std::cout << text;
    } else {
      report_file->stream() << text;
      report_file->commit();
    }
    if (!options.quiet) print_summary(result, backend->name());
    const bool over = options.fail_on > 0 && result.events.size() >= options.fail_on;
    return over ? snag::tools::kExitFound : snag::tools::kExitClean;
  });
}
