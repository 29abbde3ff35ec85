// Reads reports with the streaming reader and prints, per file, its size,
// the records of each kind and the throughput (best of --repeat runs, the
// file in the page cache after the first): the figure behind "reading a
// report back streams at N MB/s".
//
//   snag-bench-report-read [--repeat N] REPORT...
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "report/report_reader.hpp"

namespace {

struct Counts {
  std::size_t frames = 0, events = 0, regions = 0, tracks = 0;
};

Counts read_all(const std::string& path) {
  snag::report::ReportReader reader(path);
  Counts counts;
  using Record = snag::report::ReportReader::Record;
  for (Record r = reader.next(); r != Record::kEnd; r = reader.next()) {
    counts.frames += r == Record::kFrame;
    counts.events += r == Record::kEvent;
    counts.regions += r == Record::kRegion;
    counts.tracks += r == Record::kTrack;
  }
  return counts;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 3;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else {
      paths.push_back(arg);
    }
  }
  if (paths.empty()) {
    std::fprintf(stderr, "usage: snag-bench-report-read [--repeat N] REPORT...\n");
    return 2;
  }
  try {
    for (const std::string& path : paths) {
      struct stat info {};
      if (::stat(path.c_str(), &info) != 0) throw std::runtime_error(path + ": cannot stat");
      const double megabytes = static_cast<double>(info.st_size) / 1e6;
      double best = 1e300;
      Counts counts;
      for (int r = 0; r < repeat; ++r) {
        const auto start = std::chrono::steady_clock::now();
        counts = read_all(path);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      std::printf("%s: %.1f MB, %zu frames, %zu events, %zu regions, %zu tracks; best of %d: %.3f s, %.0f MB/s\n",
                  path.c_str(), megabytes, counts.frames, counts.events, counts.regions, counts.tracks, repeat, best,
                  megabytes / best);
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "snag-bench-report-read: %s\n", error.what());
    return 2;
  }
  return 0;
}
