// snag-bench: speed against accuracy of CCD methods (Provot's cubic in float
// and double, snag's filter alone, certified, exact) on query sets with exact
// ground truth, on generated stability families and on scenes; what each
// scene needed; the broad phases side by side. JSON, an HTML page, PNG charts.
#include "snag/config.hpp"

#if SNAG_HAVE_CGAL
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "exporters/bench_page.hpp"
#include "libcd/core/error.hpp"
#include "tools/bench/bench_results.hpp"
#include "tools/bench/chart_png.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/run_tool.hpp"

namespace {

struct BenchOptions {
  std::vector<std::string> queries, families;
  bool quick = false, no_families = false, quiet = false;
  int samples = 0, repeats = 0;  // 0: the default for the mode
  std::size_t steps = 4;
  std::size_t brute_force_max_triangles = 20000;
  unsigned threads = 0;
  std::string json, html, png;
};

/// Writes `text` to `path` ("-" = standard output); throws UsageError naming the file.
template <typename Write>
void write_file(const std::string& path, const char* option, Write write) {
  if (path == "-") {
    write(std::cout);
    std::cout.flush();
    return;
  }
  std::ofstream out(path, std::ios::binary);
  if (out) write(out);
  out.close();
  if (!out) throw snag::UsageError(std::string(option) + " " + path + ": cannot be written");
}

std::vector<std::string> chart_ids(const snag::bench::BenchResults& results) {
  std::vector<std::string> ids;
  if (!results.query_sets.empty() || !results.scenes.empty()) ids = {"speed-fn", "speed-fp"};
  for (const auto& family : results.families) ids.push_back("family-" + family.family.name);
  for (std::size_t i = 0; i < results.scenes.size(); ++i) {
    ids.push_back("scene-" + std::to_string(i) + "-tiers");
    ids.push_back("scene-" + std::to_string(i) + "-broad");
  }
  return ids;
}

int run_bench(const snag::tools::CacheArguments& cache, const BenchOptions& options) {
  namespace bench = snag::bench;
  if (!options.png.empty() && options.html.empty()) throw snag::UsageError("--png needs --html (the charts' page)");
  const std::string chromium = options.png.empty() ? "" : bench::chromium_path();
  if (!options.png.empty() && chromium.empty())
    throw snag::UsageError("--png: chromium is not installed (scripts/setup.sh installs it); set SNAG_CHROMIUM");
  bench::BenchResults results;
  results.quick = options.quick;
  results.repeats = options.repeats > 0 ? options.repeats : (options.quick ? 1 : 3);
  results.threads = options.threads;
  const int samples = options.samples > 0 ? options.samples : (options.quick ? 20 : 100);

  for (const std::string& dir : options.queries) {
    for (auto& set : bench::benchmark_query_sets(dir, results.repeats)) results.query_sets.push_back(std::move(set));
  }
  if (!options.no_families) results.families = bench::benchmark_families(samples, options.families);
  if (!cache.inputs.empty()) {
    auto source = snag::io::open_cache(snag::tools::to_cache_options(cache));
    bench::SceneBenchmarkSettings settings;
    settings.max_steps = options.quick ? std::min<std::size_t>(options.steps, 1) : options.steps;
    settings.threads = options.threads;
    settings.repeats = results.repeats;
    settings.brute_force_max_triangles = options.brute_force_max_triangles;
    const std::filesystem::path first(cache.inputs.front());
    const std::string name = (first.parent_path().filename() / first.stem()).string();
    results.scenes.push_back(bench::benchmark_scene(*source, name, settings));
  }
  if (results.query_sets.empty() && results.families.empty() && results.scenes.empty())
    throw snag::UsageError("nothing to benchmark: give --queries DIR, a cache, or leave the families on");

  const nlohmann::json json = bench::bench_json(results);
  if (!options.json.empty()) write_file(options.json, "--json", [&](std::ostream& out) { out << json.dump(1) << "\n"; });
  if (!options.html.empty())
    write_file(options.html, "--html", [&](std::ostream& out) { snag::exporters::write_bench_page(out, json); });
  std::vector<std::string> pngs;
  if (!options.png.empty()) {
    pngs = bench::render_chart_pngs(chromium, std::filesystem::absolute(options.html).string(), chart_ids(results),
                                    options.png);
  }
  if (!options.quiet && options.json != "-") {
    bench::print_bench_summary(stdout, results);
    for (const std::string& png : pngs) std::printf("chart: %s\n", png.c_str());
  }
  return bench::exact_methods_agree(results) ? snag::tools::kExitClean : snag::tools::kExitFound;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-bench: speed against accuracy of CCD methods (Provot's cubic in float and double, snag's "
               "filter alone, certified, exact) on query sets, stability families and a scene, and the broad "
               "phases side by side.\n"
               "  snag-bench [--queries DIR] [CACHE...] [--json FILE] [--html FILE [--png DIR]] [--quick]"};
  snag::tools::CacheArguments cache;
  BenchOptions options;
  snag::tools::add_cache_options(app, cache);
  app.get_option("inputs")->required(false)->description(
      "A scene: the cache inputs as for snag-scan (mesh files, patterns, globs, directories, point caches with\n"
      "--topology, animated files; --sequence t0.ply t1.ply for a two-frame step)");
  app.add_option("--queries", options.queries,
                 "A CCD query folder or tree with exact ground truth (repeatable)")
      ->type_name("DIR")
      ->allow_extra_args(false);
  app.add_flag("--quick", options.quick, "Few samples, one timed pass, one step of the scene (CI)");
  app.add_option("--families", options.families, "Only these stability families (default: all)")
      ->delimiter(',')
      ->type_name("LIST")
      ->allow_extra_args(false);
  app.add_flag("--no-families", options.no_families, "Leave out the generated stability families");
  app.add_option("--samples", options.samples, "Queries per knob value of each family (default 100, --quick 20)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--repeat", options.repeats, "Timed passes per method, the fastest kept (default 3, --quick 1)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--steps", options.steps, "Steps of the scene measured, from its first frame (default 4)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--brute-force-max-triangles", options.brute_force_max_triangles,
                 "Skip the brute-force broad phase on scenes with more triangles (default 20000)");
  app.add_option("-j,--threads", options.threads, "Broad-phase threads (0 = all cores); CCD methods run on one");
  app.add_option("--json", options.json, "Write every number as JSON (- = standard output)")->type_name("FILE");
  app.add_option("--html", options.html, "Write the self-contained page with the charts")->type_name("FILE");
  app.add_option("--png", options.png, "Render each chart of the page to DIR/snag-bench-ID.png (headless chromium)")
      ->type_name("DIR");
  app.add_flag("-q,--quiet", options.quiet, "Print no table");
  if (int code = snag::tools::parse_command_line(app, argc, argv); code >= 0) return code;

  return snag::tools::run_tool("snag-bench", [&] {
    std::unique_ptr<tbb::global_control> thread_limit;
    if (options.threads > 0) {
      thread_limit =
          std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, options.threads);
    }
    return run_bench(cache, options);
  });
}

#else  // !SNAG_HAVE_CGAL

#include <cstdio>

int main() {
  std::fprintf(stderr, "snag-bench: error: the exact method needs CGAL; configure with -DSNAG_WITH_CGAL=ON\n");
  return 2;
}

#endif
