// snag-bench-report-sink: the report sink's own time per frame, away from
// the scan. Scans the step t0 -> t1 -> t0 once on the CPU, keeps each
// frame's events and positions, then feeds a ReportSink the frames
// t0 t1 t0 t1 ... (as snag-scan --sequence t0 t1 t0 t1 ... does), through
// the scan's sink threads with the scan's room (two frames in the sink,
// digested at once), and times them from the first frame handed to the
// end of the finish() that waits for the last frame's join:
// wall and CPU time of the process (the sink's threads and the threads it
// formats events on; nothing else runs then), so that the
// number holds on a machine that other work shares. The report goes to
// /dev/null. Beside the whole sink, the same frames' regions (RegionBuilder,
// every event in a region: the sink with no rules) and tracks (TrackBuilder)
// are timed alone; the rest of the sink is the rules, counts, event records
// and writing.
//
//   snag-bench-report-sink T0 T1 [FRAMES] [RUNS] [MAX_EVENTS] [THREADS] [STEP_MS]
//
// Defaults 12, 3, snag-scan's --max-events default, 100000 (0: every event
// listed), every core (THREADS caps the threads of the sink's work), and 0.
//
// With STEP_MS above 0 the frames are handed as a scan whose step takes
// that long would hand them (a step's time on this thread, then the frame),
// and the scan's wait for the sink is timed: what a quick back end waits for
// the report (the first frames, which list the most events, and the
// digesters' first use among them), as a sum over the run of the waits to
// hand a frame. The sink's own figures then include the time between frames.
//
// Prints one JSON object: events per frame, and per-frame milliseconds
// (median over runs of each run's mean) of the sink, wall and CPU, and of
// its regions and tracks, wall and CPU, and the scan's wait in ms (median
// over runs of each run's sum).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>

#include "io/open_cache.hpp"
#include "libcd/pipeline/backend.hpp"
#include "libcd/pipeline/scan.hpp"
#include "libcd/pipeline/sink_thread.hpp"
#include "report/regions.hpp"
#include "report/report_sink.hpp"
#include "report/report_writer.hpp"
#include "report/rules.hpp"

namespace {

using snag::Event;
using snag::Vec3;

struct Recorded {
  std::vector<Event> events;
  std::vector<Vec3> x;
};

// Keeps each scanned frame's events and positions.
class RecordingSink : public snag::ScanSink {
 public:
  void frame(snag::ScannedFrame& frame) override { frames.push_back({*frame.events, *frame.x}); }
  std::vector<Recorded> frames;
};

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int run(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s T0 T1 [FRAMES] [RUNS] [MAX_EVENTS] [THREADS] [STEP_MS]\n", argv[0]);
    return 2;
  }
  const std::size_t frames = argc > 3 ? std::stoul(argv[3]) : 12;
  const std::size_t runs = argc > 4 ? std::stoul(argv[4]) : 3;
  const std::size_t max_events = argc > 5 ? std::stoul(argv[5]) : 100000;
  const std::size_t threads = argc > 6 ? std::stoul(argv[6]) : 0;
  const double step_ms = argc > 7 ? std::stod(argv[7]) : 0.0;
  if (frames < 2 || runs < 1 || threads > 4096 || !(step_ms >= 0 && step_ms <= 1e4)) {
    std::fprintf(stderr, "%s: FRAMES must be at least 2, RUNS at least 1, THREADS at most 4096, STEP_MS in [0, 1e4]\n",
                 argv[0]);
    return 2;
  }

  snag::io::CacheOptions cache;
  snag::io::InputSpec input;
  input.frame_files = {argv[1], argv[2], argv[1]};
  cache.inputs.push_back(input);
  auto source = snag::io::open_cache(cache);
  const snag::Scene& scene = source->scene();
  const snag::report::RuleSet rules(scene, {}, 0.0);
  auto backend = snag::make_cpu_backend();
  backend->bind(scene, snag::BackendSettings{});
  RecordingSink recorded;
  snag::scan_cache(*source, *backend, snag::ScanSettings{}, recorded, {});
  // Frames 0 and 1 of the scan: the steps t0 -> t1 and t1 -> t0 with each frame's intersections.
  recorded.frames.resize(2);

  snag::report::Header header;
  header.source = source->description();
  for (const snag::Object& object : scene.objects()) {
    header.objects.push_back({object.name, object.vertex_count, snag::file_vertex_count(object),
                              object.triangles.size(), object.edges.size(), object.weld.method, 0.0});
  }
  header.frame_count = frames;
  header.settings.max_events = max_events;

  // The scan above used every core; the sink's work gets THREADS of them.
  std::unique_ptr<tbb::global_control> thread_cap;
  if (threads > 0)
    thread_cap = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

  std::vector<double> wall_ms, cpu_ms, regions_ms, tracks_ms, regions_cpu_ms, tracks_cpu_ms, scan_wait_ms;
  std::size_t events = 0;
  for (std::size_t run = 0; run < runs; ++run) {
    std::ofstream null("/dev/null");
    snag::report::ReportWriter writer(null);
    snag::report::ReportSink sink(scene, header, rules, &writer);
    // Each frame's own list (the sink may change it in place until it is
    // done with the frame), made before the clock starts.
    std::vector<std::vector<Event>> lists(frames);
    for (std::size_t position = 0; position < frames; ++position) {
      lists[position] = recorded.frames[position % 2].events;
      for (Event& e : lists[position]) e.frame = position;
      events += lists[position].size();
    }
    const auto wall_start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    double scan_wait = 0;
    {
      snag::SinkThread thread(sink, snag::kScanFramesInSink);
      for (std::size_t position = 0; position < frames; ++position) {
        snag::ScannedFrame frame;
        frame.position = position;
        frame.time = static_cast<double>(position);
        frame.summary.frame = position;
        frame.events = &lists[position];
        frame.x = &recorded.frames[position % 2].x;
        frame.x_next = position + 1 < frames ? &recorded.frames[(position + 1) % 2].x : nullptr;
        if (step_ms > 0) {
          std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(step_ms));
          const auto handing = std::chrono::steady_clock::now();
          thread.hand(frame);
          scan_wait += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - handing).count();
        } else {
          thread.hand(frame);
        }
      }
      thread.drain();
    }
    // The last frame's join may still run: finish() waits for it.
    sink.finish("{}", "{}");
    const double cpu = process_cpu_seconds() - cpu_start;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    wall_ms.push_back(1e3 * wall / static_cast<double>(frames));
    cpu_ms.push_back(1e3 * cpu / static_cast<double>(frames));
    scan_wait_ms.push_back(scan_wait);

    snag::report::RegionBuilder regions(scene);
    snag::report::TrackBuilder tracks(scene);
    std::vector<snag::report::RegionRecord> frame_regions;
    std::vector<snag::report::TrackRecord> ended;
    std::vector<std::size_t> region_of;
    double region_seconds = 0, track_seconds = 0, region_cpu = 0, track_cpu = 0;
    for (std::size_t position = 0; position < frames; ++position) {
      const Recorded& r = recorded.frames[position % 2];
      const std::vector<char> in_region(r.events.size(), 1);
      frame_regions.clear();
      ended.clear();
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = process_cpu_seconds();
      regions.build(r.events, in_region, r.x, position, frame_regions, region_of);
      const auto built = std::chrono::steady_clock::now();
      const double cpu_built = process_cpu_seconds();
      tracks.add_frame(position, position, frame_regions, ended);
      region_seconds += std::chrono::duration<double>(built - start).count();
      track_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count();
      region_cpu += cpu_built - cpu_start;
      track_cpu += process_cpu_seconds() - cpu_built;
    }
    regions_ms.push_back(1e3 * region_seconds / static_cast<double>(frames));
    tracks_ms.push_back(1e3 * track_seconds / static_cast<double>(frames));
    regions_cpu_ms.push_back(1e3 * region_cpu / static_cast<double>(frames));
    tracks_cpu_ms.push_back(1e3 * track_cpu / static_cast<double>(frames));
  }
  std::printf("{\"frames\":%zu,\"runs\":%zu,\"max_events\":%zu,\"threads\":%zu,\"events_per_frame\":%.0f,"
              "\"sink_wall_ms_per_frame\":%.2f,\"sink_cpu_ms_per_frame\":%.2f,\"regions_ms_per_frame\":%.2f,"
              "\"regions_cpu_ms_per_frame\":%.2f,\"tracks_ms_per_frame\":%.2f,\"tracks_cpu_ms_per_frame\":%.2f,"
              "\"step_ms\":%g,\"scan_wait_ms\":%.2f}\n",
              frames, runs, max_events, threads, static_cast<double>(events) / static_cast<double>(frames * runs),
              median(wall_ms), median(cpu_ms), median(regions_ms), median(regions_cpu_ms), median(tracks_ms),
              median(tracks_cpu_ms), step_ms, median(scan_wait_ms));
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::logic_error&) {  // std::stoul: not a number
    std::fprintf(stderr, "%s: FRAMES, RUNS, MAX_EVENTS and THREADS must be whole numbers, STEP_MS a number\n",
                 argv[0]);
    return 2;
  } catch (const std::exception& error) {  // a mesh that cannot be read, a count that is not one
    std::fprintf(stderr, "%s: %s\n", argv[0], error.what());
    return 2;
  }
}
