// snag-scan --batch LIST: many scenes in one run, each with its own report,
// spread over the run's ranks by size (largest first, each to the least
// loaded rank), and a batch summary: the list of the reports, which
// snag-report --list reads to make one page of the batch.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace snag::tools {

/// One line of a batch list.
struct BatchScene {
  std::string input;   ///< a scene manifest (.yaml, .yml) or a cache input, as snag-scan takes it
  bool manifest = false;
  std::string report;  ///< DIR/NAME.jsonl, NAME the input's file name without its extension
  std::size_t line = 0;
};

/// Reads a batch list: one scene per line, relative paths taken from the
/// list's directory, blank lines and lines starting with '#' skipped.
/// Reports go to `report_dir`. Throws InputError (file, line) for an empty
/// list or two scenes whose reports would have one name.
std::vector<BatchScene> read_batch_list(const std::string& path, const std::string& report_dir);

/// Splits scenes of sizes `sizes` over `ranks`: largest first (list order
/// among equals), each to the rank with the least so far (the lowest among
/// equals). Returns each rank's scene indices in list order.
std::vector<std::vector<std::size_t>> assign_by_size(const std::vector<std::size_t>& sizes, std::size_t ranks);

/// Bytes of the files a scene names: its regular files, or a directory's
/// files; 0 for patterns and globs. `inputs`: the cache inputs (topology meshes included).
std::size_t input_bytes(const std::vector<std::string>& inputs);

/// Writes the batch summary DIR/batch.txt (each report's file name, one a
/// line, in list order: a path list, read_path_list(), from DIR) when complete, and prints a line per scene (verdict and
/// counts, read from its report) on standard output unless `quiet`.
void write_batch_summary(const std::vector<BatchScene>& scenes, const std::string& report_dir, bool quiet);

}  // namespace snag::tools
