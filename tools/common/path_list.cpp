#include "tools/common/path_list.hpp"

#include <filesystem>
#include <fstream>

#include "libcd/core/error.hpp"

namespace snag::tools {

std::vector<ListedPath> read_path_list(const std::string& list) {
  namespace fs = std::filesystem;
  std::ifstream in(list);
  if (!in) throw InputError(InputLocation{list}, "cannot read the list");
  const fs::path base = fs::path(list).parent_path();
  std::vector<ListedPath> paths;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    const auto last = text.find_last_not_of(" \t\r");
    const fs::path path = text.substr(first, last - first + 1);
    paths.push_back({(path.is_absolute() ? path : base / path).string(), line});
  }
  if (in.bad()) throw InputError(InputLocation{list}, "cannot read the list");
  return paths;
}

}  // namespace snag::tools
