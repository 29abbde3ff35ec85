#include "io/frame_files.hpp"

#include <glob.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <system_error>

#include "io/mesh_file.hpp"
#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

namespace fs = std::filesystem;

namespace {

struct SplitPath {
  std::string directory;  ///< "" for the working directory, else ends without '/'
  std::string name;
};

SplitPath split_path(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return {"", path};
  return {slash == 0 ? "/" : path.substr(0, slash), path.substr(slash + 1)};
}

std::string join(const std::string& directory, const std::string& name) {
  if (directory.empty()) return name;
  if (directory.back() == '/') return directory + name;
  return directory + "/" + name;
}

/// The number carried by a file name: its last digit run, or -1.
double last_number(const std::string& path) {
  const std::string name = file_stem(path);
  std::size_t end = name.size();
  while (end > 0 && !(name[end - 1] >= '0' && name[end - 1] <= '9')) --end;
  if (end == 0) return -1;
  std::size_t start = end;
  while (start > 0 && name[start - 1] >= '0' && name[start - 1] <= '9' && end - start < 15) --start;
  return std::stod(name.substr(start, end - start));
}

std::vector<FrameFile> numbered_in_natural_order(std::vector<std::string> paths) {
  std::sort(paths.begin(), paths.end(), natural_less);
  std::vector<FrameFile> files;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const double number = last_number(paths[i]);
    files.push_back({paths[i], number >= 0 ? number : static_cast<double>(i)});
  }
  return files;
}

/// Position and length of the one integer conversion in a printf pattern, or
/// npos when there is none; throws for other conversions or several.
std::pair<std::size_t, std::size_t> find_conversion(const std::string& pattern, const std::string& whole) {
  std::size_t found = std::string::npos, length = 0;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && j - i < 3) ++j;
    if (j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i') || found != std::string::npos) {
      throw InputError({whole}, "bad frame pattern: expected one %d, %0Nd or %Nd conversion in the file name");
    }
    found = i;
    length = j + 1 - i;
    i = j;
  }
  return {found, length};
}

std::string unescape_percent(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '%' && i + 1 < text.size() && text[i + 1] == '%') ++i;
  }
  return out;
}

}  // namespace

bool is_frame_pattern(const std::string& path) {
  const std::string name = split_path(path).name;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (name[i] != '%') continue;
    if (i + 1 < name.size() && name[i + 1] == '%') {
      ++i;
      continue;
    }
    return true;
  }
  return false;
}

bool is_glob(const std::string& path) { return path.find_first_of("*?[") != std::string::npos; }

std::vector<FrameFile> list_pattern_files(const std::string& pattern) {
  const SplitPath split = split_path(pattern);
  const auto [at, length] = find_conversion(split.name, pattern);
  if (at == std::string::npos) throw InputError({pattern}, "bad frame pattern: no %d conversion in the file name");
  const std::string prefix = unescape_percent(split.name.substr(0, at));
  const std::string suffix = unescape_percent(split.name.substr(at + length));
  std::error_code error;
  fs::directory_iterator entries(split.directory.empty() ? fs::path(".") : fs::path(split.directory), error);
  if (error) throw InputError({pattern}, "cannot list the pattern's directory: " + error.message());
  std::vector<FrameFile> files;
  std::vector<char> printed(split.name.size() + 64);
  for (const fs::directory_entry& entry : entries) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const int number = std::stoi(digits);
    // Print the number back through the pattern (validated above to hold one
    // integer conversion) so "%04d" does not take "1" or "00001".
    std::snprintf(printed.data(), printed.size(), split.name.c_str(), number);
    if (name != printed.data() || !entry.is_regular_file(error)) continue;
    files.push_back({join(split.directory, name), static_cast<double>(number)});
  }
  if (files.empty()) throw InputError({pattern}, "no files match the frame pattern");
  std::sort(files.begin(), files.end(), [](const FrameFile& a, const FrameFile& b) { return a.number < b.number; });
  return files;
}

std::vector<FrameFile> list_glob_files(const std::string& pattern) {
  glob_t matches{};
  const int status = ::glob(pattern.c_str(), GLOB_NOSORT, nullptr, &matches);
  std::vector<std::string> paths;
  if (status == 0) {
    for (std::size_t i = 0; i < matches.gl_pathc; ++i) {
      std::error_code error;
      if (fs::is_regular_file(matches.gl_pathv[i], error)) paths.emplace_back(matches.gl_pathv[i]);
    }
  }
  ::globfree(&matches);
  if (paths.empty()) throw InputError({pattern}, "no files match the glob");
  return numbered_in_natural_order(std::move(paths));
}

std::vector<FrameFile> list_directory_files(const std::string& directory) {
  std::error_code error;
  fs::directory_iterator entries(directory, error);
  if (error) throw InputError({directory}, "cannot list the directory: " + error.message());
  std::map<std::string, std::vector<std::string>> by_extension;
  for (const fs::directory_entry& entry : entries) {
    const std::string path = join(directory, entry.path().filename().string());
    const std::string extension = lower_extension(path);
    if (is_mesh_extension(extension) && entry.is_regular_file(error)) by_extension[extension].push_back(path);
  }
  if (by_extension.empty()) throw InputError({directory}, "the directory holds no mesh files");
  if (by_extension.size() > 1) {
    std::string kinds;
    for (const auto& [extension, paths] : by_extension) kinds += (kinds.empty() ? "." : ", .") + extension;
    throw InputError({directory}, "the directory holds mesh files of several formats (" + kinds +
                                      "); name the frames with a pattern or glob");
  }
  return numbered_in_natural_order(std::move(by_extension.begin()->second));
}

}  // namespace snag::io
