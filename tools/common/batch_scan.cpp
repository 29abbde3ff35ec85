#include "tools/common/batch_scan.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include "libcd/core/error.hpp"
#include "report/report_reader.hpp"
#include "report/summary.hpp"
#include "tools/common/path_list.hpp"
#include "tools/common/replacing_file.hpp"

namespace snag::tools {

namespace fs = std::filesystem;

namespace {

InputError list_error(const std::string& path, std::size_t line, const std::string& message) {
  InputLocation where{path};
  where.line = line;
  return InputError(where, message);
}

bool is_manifest(const fs::path& path) {
  const std::string extension = path.extension().string();
  return extension == ".yaml" || extension == ".yml";
}

}  // namespace

std::vector<BatchScene> read_batch_list(const std::string& path, const std::string& report_dir) {
  std::vector<BatchScene> scenes;
  std::map<std::string, std::size_t> line_of_report;
  for (const ListedPath& listed : read_path_list(path)) {
    const fs::path input = listed.path;
    BatchScene scene;
    scene.input = listed.path;
    scene.manifest = is_manifest(input);
    scene.line = listed.line;
    std::string name = input.stem().string();
    std::replace(name.begin(), name.end(), '%', '_');
    std::replace(name.begin(), name.end(), '*', '_');
    scene.report = (fs::path(report_dir) / (name + ".jsonl")).string();
    const auto [it, inserted] = line_of_report.emplace(scene.report, listed.line);
    if (!inserted) {
      throw list_error(path, listed.line, "its report " + scene.report + " would overwrite that of line " +
                                              std::to_string(it->second) + ": give the scenes different file names");
    }
    scenes.push_back(scene);
  }
  if (scenes.empty()) throw list_error(path, 0, "the batch list names no scene");
  return scenes;
}

std::vector<std::vector<std::size_t>> assign_by_size(const std::vector<std::size_t>& sizes, std::size_t ranks) {
  std::vector<std::size_t> order(sizes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
  std::vector<std::vector<std::size_t>> assigned(ranks);
  std::vector<std::size_t> load(ranks, 0);
  for (std::size_t scene : order) {
    const std::size_t rank = std::min_element(load.begin(), load.end()) - load.begin();
    assigned[rank].push_back(scene);
    load[rank] += sizes[scene];
  }
  for (auto& scenes : assigned) std::sort(scenes.begin(), scenes.end());
  return assigned;
}

std::size_t input_bytes(const std::vector<std::string>& inputs) {
  std::size_t bytes = 0;
  std::error_code error;
  for (const std::string& input : inputs) {
    if (fs::is_regular_file(input, error)) {
      bytes += fs::file_size(input, error);
    } else if (fs::is_directory(input, error)) {
      for (const auto& entry : fs::directory_iterator(input, error)) {
        if (entry.is_regular_file(error)) bytes += entry.file_size(error);
      }
    }
  }
  return bytes;
}

void write_batch_summary(const std::vector<BatchScene>& scenes, const std::string& report_dir, bool quiet) {
  ReplacingFile summary((fs::path(report_dir) / "batch.txt").string());
  std::size_t failed = 0;
  for (const BatchScene& scene : scenes) {
    report::ReportReader reader(scene.report);
    while (reader.next() != report::ReportReader::Record::kTrailer) {
    }
    const report::Trailer& trailer = reader.trailer();
    failed += !trailer.pass;
    // Its name in DIR: snag-report --list takes paths from the list's directory.
    summary.stream() << fs::path(scene.report).filename().string() << '\n';
    if (!quiet) {
      std::printf("%s: %zu events (%zu collisions, %zu intersections), %zu regions, %zu tracks: %s\n",
                  scene.report.c_str(), trailer.events, trailer.collisions, trailer.intersections, trailer.regions,
                  trailer.tracks, report::verdict_text(trailer).c_str());
    }
  }
  summary.commit();
  if (!quiet) {
    std::printf("batch: %zu scenes, %zu failed; summary: %s\n", scenes.size(), failed,
                (fs::path(report_dir) / "batch.txt").string().c_str());
  }
}

}  // namespace snag::tools
