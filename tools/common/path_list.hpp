// Lists of files, one path a line: snag-scan --batch's scenes, snag-report
// --list's reports (the batch summary DIR/batch.txt is one).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace snag::tools {

/// A path named by a list, and the line that named it (1-based).
struct ListedPath {
  std::string path;  ///< relative paths taken from the list's directory
  std::size_t line = 0;
};

/// Reads a list: one path a line, surrounding blanks trimmed, blank lines
/// and lines starting with '#' skipped, relative paths taken from the list's
/// directory. Throws InputError naming the list when it cannot be read.
std::vector<ListedPath> read_path_list(const std::string& list);

}  // namespace snag::tools
