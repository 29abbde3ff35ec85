#include "tools/bench/chart_png.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "libcd/core/error.hpp"

namespace snag::bench {

namespace {

/// `text` as one single-quoted shell word.
std::string shell_word(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string chromium_path() {
  if (const char* given = std::getenv("SNAG_CHROMIUM")) return given;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    for (const char* name : {"chromium", "chromium-browser"}) {
      const std::string candidate = dir + "/" + name;
      if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
  }
  return "";
}

std::vector<std::string> render_chart_pngs(const std::string& chromium, const std::string& page,
                                           const std::vector<std::string>& chart_ids, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const fs::path profile = fs::path(dir) / ".chromium-profile";
  std::vector<std::string> written;
  for (const std::string& id : chart_ids) {
    const std::string png = (fs::path(dir) / ("snag-bench-" + id + ".png")).string();
    fs::remove(png);
    // Headless, software only, a fixed window; the virtual time budget lets
    // the page's script finish before the screenshot.
    const std::string command =
        "timeout 120 " + shell_word(chromium) +
        " --headless --no-sandbox --disable-gpu --no-first-run --hide-scrollbars --window-size=900,540"
        " --virtual-time-budget=5000 --user-data-dir=" +
        shell_word(profile.string()) + " --screenshot=" + shell_word(png) + " " +
        shell_word("file://" + page + "#only=" + id) + " >/dev/null 2>&1";
    const int status = std::system(command.c_str());
    if (status != 0 || !fs::exists(png) || fs::file_size(png) == 0)
      throw UsageError("--png: " + chromium + " did not render the chart " + id + " of " + page);
    written.push_back(png);
  }
  fs::remove_all(profile);
  return written;
}

}  // namespace snag::bench
