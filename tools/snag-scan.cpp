// snag-scan: finds every collision between consecutive frames (CCD) and every
// intersection within a frame (DCD) of a cache, joins them into regions and
// tracks, judges them by the rules, streams the report and prints a summary.
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <set>

#include "libcd/core/error.hpp"
#include "libcd/cpu/cpu_backend.hpp"
#include "libcd/pipeline/pair_thickness.hpp"
#include "libcd/pipeline/scan.hpp"
#include "report/report_sink.hpp"
#include "report/summary.hpp"
#include "snag/config.hpp"
#include "tools/common/batch_scan.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/replacing_file.hpp"
#include "tools/common/rule_options.hpp"
#include "tools/common/run_tool.hpp"
#include "tools/common/scan_stats.hpp"
#if SNAG_HAVE_MPI
#include "tools/common/mpi_scan.hpp"
#endif
#if SNAG_HAVE_CGAL
#include "validate/exact_certifier.hpp"
#endif
#if SNAG_HAVE_CUDA
#include "libcd/cuda/cuda_backend.hpp"
#include "libcd/cuda/device.hpp"
#endif

namespace snag::tools::mpi {
class Run;  // tools/common/mpi_scan.hpp, in builds with MPI
}

namespace {

struct ScanOptions {
  std::string mode = "all";
  double thickness = 0;
  std::string backend = "auto";
  std::string grid = "uniform";  ///< --grid: adaptive subdivides crowded cells (either back end)
  unsigned threads = 0;
  double lambda = snag::kDefaultLambda;
  std::size_t device_memory = 0;  ///< --device-memory, bytes (0: what the GPU has free)
  std::string report;
  std::string events = "all";
  std::size_t max_events = 100000;
  bool json = false;
  bool quiet = false;
  std::string precision = "certified";
  bool mpi = false;
  std::string batch;  ///< --batch LIST
};

// auto: the CUDA back end when this build has it and a usable device is
// present, else the CPU one. cuda: the CUDA back end or a usage error (exit 2)
// saying why it cannot run.
std::unique_ptr<snag::Backend> choose_backend(const std::string& requested, const std::string& grid) {
  const snag::BroadPhaseMethod method =
      grid == "adaptive" ? snag::BroadPhaseMethod::kAdaptiveGrid : snag::BroadPhaseMethod::kVirtualSubdivisionGrid;
  auto cpu_backend = [&] {
    return method == snag::BroadPhaseMethod::kAdaptiveGrid ? snag::make_cpu_backend(snag::CpuBackendOptions{method})
                                                           : snag::make_cpu_backend();
  };
  if (requested == "cpu") return cpu_backend();
#if SNAG_HAVE_CUDA
  const snag::CudaDeviceInfo device = snag::query_cuda_device();
  if (device.available) return snag::make_cuda_backend(method);
  if (requested == "cuda") throw snag::UsageError("--backend cuda: " + device.why_not);
#else
  if (requested == "cuda") {
    throw snag::UsageError("--backend cuda: this build has no CUDA back end: configure with -DSNAG_WITH_CUDA=ON");
  }
#endif
  return cpu_backend();
}

// Threads of a scan beside the CUDA back end that want a core of their own
// while the device is busiest, besides the thread pools' workers: the back
// end's two detection workers and its event copier, the frame reader, and the
// scan's, the sink's and the report's joining threads, which run their pools'
// tasks beside the workers. A pool capped at N threads has N - 1 workers, so
// a cap of all cores but six gives each of these seven a core.
constexpr unsigned kThreadsBesideTheWorkers = 6;

// The most threads the scan's parallel work (the back end's host work, the
// report's) may use at once: --threads when given, else every core, and
// beside the CUDA back end on more than six cores all but
// kThreadsBesideTheWorkers, and at least half. With more, a busy pool kept
// the detection workers from their cores: the next step's detection then
// started up to 2 ms late (cloth_ball, CCD + static, 42 frames, 16 cores, 6
// interleaved runs: a median of 7.2 ms a step with a cap of 13, 6.6 with 10,
// and 7.6 with 8). Measured again with CCD + static, 5 interleaved runs on
// 16 cores (H100), caps 10, 13 and 16: cloth_ball 3.59, 4.10 and 4.39 ms a
// step, ×4 9.89, 10.38 and 10.92, ×16 52.9, 53.1 and 53.2.
unsigned host_threads(unsigned requested, bool cuda) {
  if (requested > 0) return requested;
  const auto cores = static_cast<unsigned>(std::max(1, tbb::info::default_concurrency()));
  if (!cuda || cores <= kThreadsBesideTheWorkers) return cores;
  return std::max(cores - kThreadsBesideTheWorkers, cores / 2);
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
  s.grid = options.grid;
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

// Scans one cache into one report. With `run` (under MPI), every rank
// scans a range of the steps and rank 0 writes the report; `run` is null
// for a single process.
int scan(const snag::tools::CacheArguments& cache, const snag::tools::RuleArguments& rule_arguments,
         const ScanOptions& options, std::optional<double> thickness_option, snag::tools::mpi::Run* run) {
  if (options.json && options.report == "-") {
    throw snag::UsageError("--json and --report - both write to standard output: give the report a file");
  }
  const auto begun = std::chrono::steady_clock::now();
  const snag::tools::ScanSetup setup = snag::tools::resolve_scan_setup(cache, rule_arguments, thickness_option);
  // The back end is made while the cache is opened: a GPU's context takes a
  // few hundred milliseconds to start. Its errors come after the cache's,
  // as they would one after the other.
  auto making_backend = std::async(std::launch::async, [&] { return choose_backend(options.backend, options.grid); });
  auto source = snag::io::open_cache(setup.cache);
  const snag::Scene& scene = source->scene();
  check_object_names(scene);
  const snag::report::RuleSet rules(scene, setup.rules, setup.thickness);
  auto backend = making_backend.get();
  const tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism,
                                         host_threads(options.threads, backend->name() == "cuda"));

  snag::BackendSettings backend_settings;
  backend_settings.lambda = options.lambda;
  backend_settings.thickness = rules.max_thickness();
  backend_settings.threads = options.threads;
  backend_settings.device_memory_bytes = options.device_memory;
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
#if SNAG_HAVE_MPI
  std::vector<snag::tools::StepRange> ranges;
  if (run) {
    ranges = run->split(source->frame_count(), backend->name());
    if (run->rank() != 0) {
      run->scan_part(*source, ranges, *backend, scan, rules,
                     make_header(*source, rules, setup, options, backend->name()).settings, redecide);
      return snag::tools::kExitClean;
    }
  }
#endif
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
  std::string stages, timing;
  double seconds = 0;
  const double start_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
  if (!run) {
    const snag::ScanTotals totals = snag::scan_cache(*source, *backend, scan, sink, progress);
    stages = snag::tools::stages_json(totals);
    timing = snag::tools::timing_json(totals);
    seconds = totals.total_seconds;
  }
#if SNAG_HAVE_MPI
  else {
    const auto merged = run->scan_and_merge(*source, ranges, *backend, scan, sink, progress);
    stages = merged.stages_json;
    timing = merged.timing_json;
    seconds = merged.total_seconds;
  }
#endif
  timing = snag::tools::with_start_seconds(timing, start_seconds);
  const snag::report::Trailer& trailer = sink.finish(stages, timing);
  if (report_file) report_file->commit();

  if (options.json) {
    snag::report::ReportWriter json(std::cout);
    json.use_names_of(header);
    json.write_trailer(trailer);
  } else if (!options.quiet) {
    std::FILE* out = options.report == "-" ? stderr : stdout;
    std::fprintf(out, "snag-scan: %s on %s, %.3f s\n", source->description().c_str(), backend->name().c_str(),
                 seconds);
    snag::report::print_summary(out, header, trailer);
    if (!options.report.empty() && options.report != "-") std::fprintf(out, "report: %s\n", options.report.c_str());
  }
  return trailer.pass ? snag::tools::kExitClean : snag::tools::kExitFound;
}

// Scans every scene of the batch list this rank is given, each into its
// report; rank 0 then waits for the others (`wait_for_others` returns the
// largest of their exit codes) and writes the batch summary.
int scan_batch(const snag::tools::CacheArguments& cache, const snag::tools::RuleArguments& rule_arguments,
               const ScanOptions& options, std::optional<double> thickness_option, int rank, int ranks,
               const std::function<int()>& wait_for_others) {
  if (options.report.empty() || options.report == "-") {
    throw snag::UsageError("--batch: give --report DIR, the directory for the scenes' reports");
  }
  if (!cache.inputs.empty() || !rule_arguments.manifest.empty() || options.json) {
    throw snag::UsageError("--batch: the list names the scenes: no inputs, --manifest or --json beside it");
  }
  std::error_code error;
  std::filesystem::create_directories(options.report, error);
  if (error) throw snag::UsageError(options.report + ": cannot make the report directory: " + error.message());
  const std::vector<snag::tools::BatchScene> scenes = snag::tools::read_batch_list(options.batch, options.report);
  std::vector<snag::tools::CacheArguments> caches(scenes.size(), cache);
  std::vector<snag::tools::RuleArguments> rules(scenes.size(), rule_arguments);
  std::vector<std::size_t> sizes;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    if (scenes[i].manifest) {
      rules[i].manifest = scenes[i].input;
    } else {
      caches[i].inputs = {scenes[i].input};
    }
    const snag::tools::ScanSetup setup = snag::tools::resolve_scan_setup(caches[i], rules[i], thickness_option);
    std::vector<std::string> files;
    for (const snag::io::InputSpec& input : setup.cache.inputs) files.insert(files.end(), {input.path, input.topology});
    sizes.push_back(snag::tools::input_bytes(files));
  }
  const auto assigned = snag::tools::assign_by_size(sizes, static_cast<std::size_t>(ranks));
  int code = snag::tools::kExitClean;
  for (std::size_t i : assigned[rank]) {
    ScanOptions one = options;
    one.report = scenes[i].report;
    one.quiet = true;
    code = std::max(code, scan(caches[i], rules[i], one, thickness_option, nullptr));
  }
  if (rank != 0) return code;
  code = std::max(code, wait_for_others());
  snag::tools::write_batch_summary(scenes, options.report, options.quiet);
  return code;
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
  app.add_option("--grid", options.grid, "uniform, or adaptive (crowded cells subdivided)")
      ->check(CLI::IsMember({"uniform", "adaptive"}));
  app.add_option(
      "-j,--threads", options.threads,
      "CPU threads for the scan's parallel work (0 = all cores; beside the CUDA back end, all but six, at least half)");
  app.add_option("--lambda", options.lambda, "Cell-size coefficient of the CUDA back end's grid: cell = 3 x lambda x mean triangle radius (the CPU back end's box grid does not use it)")
      ->check(CLI::Range(1.0001, 100.0));
  app.add_option("--device-memory", options.device_memory,
                 "Most GPU memory the CUDA back end may use, e.g. 4G (default: what is free less 2 GiB);\n"
                 "larger scenes run in chunks with the same events")
      ->transform(CLI::AsSizeValue(false))
      ->type_name("BYTES");
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
  app.add_flag("--mpi", options.mpi,
               "Scan over the ranks of an MPI run (implied under mpirun): each rank scans a range of steps,\n"
               "rank 0 writes the one report");
  app.add_option("--batch", options.batch,
                 "Scan every scene of LIST (a manifest or cache input a line), each into DIR/NAME.jsonl\n"
                 "(--report DIR), and list the reports in DIR/batch.txt; under mpirun spread over the ranks")
      ->type_name("LIST");
#if SNAG_HAVE_MPI
  if (int code = snag::tools::mpi::parse_command_line_on_every_rank(app, argc, argv); code >= 0) return code;
#else
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;
#endif

  // Under mpirun every rank runs this (tools/common/mpi_scan.hpp): a scan
  // splits its steps over the ranks, a batch its scenes.
  std::optional<double> thickness_option;
  if (app.count("--thickness") > 0) thickness_option = options.thickness;
#if SNAG_HAVE_MPI
  std::optional<snag::tools::mpi::Run> mpi;
  if (options.mpi || snag::tools::mpi::launched_by_mpirun()) mpi.emplace(&argc, &argv);
  if (mpi) {
    // A scan's parts go beside its report; a batch has none.
    const std::string parts_near = !options.batch.empty() ? "" : options.report.empty() ? "." : options.report;
    return mpi->run("snag-scan", parts_near, [&] {
      if (options.batch.empty()) return scan(cache, rule_arguments, options, thickness_option, &*mpi);
      return scan_batch(cache, rule_arguments, options, thickness_option, mpi->rank(), mpi->size(),
                        [&] { return mpi->wait_for_everyone(); });
    });
  }
#else
  if (options.mpi) {
    std::fprintf(stderr, "snag-scan: error: --mpi: this build has no MPI: configure with -DSNAG_WITH_MPI=ON\n");
    return snag::tools::kExitBadInput;
  }
#endif
  return snag::tools::run_tool("snag-scan", [&] {
    if (options.batch.empty()) return scan(cache, rule_arguments, options, thickness_option, nullptr);
    return scan_batch(cache, rule_arguments, options, thickness_option, 0, 1, [] { return snag::tools::kExitClean; });
  });
}
