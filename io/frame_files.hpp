// The files of a per-frame mesh sequence, named by a printf-style pattern, a
// glob or a directory, in frame order.
#pragma once

#include <string>
#include <vector>

namespace snag::io {

struct FrameFile {
  std::string path;
  /// The frame number the file name carries (pattern: the number substituted;
  /// glob and directory: the last digit run of the file name; else its rank).
  double number = 0;
};

/// True when `path` holds a printf-style frame number ("%d", "%04d", "%4d").
bool is_frame_pattern(const std::string& path);
/// True when `path` holds glob characters (*, ?, [).
bool is_glob(const std::string& path);

/// Files matching a pattern such as "cache/cloth_%04d.obj" (one conversion,
/// in the file name), sorted by number. A name matches only if printing its
/// number with the pattern gives the name back. Throws InputError when the
/// pattern is malformed or nothing matches.
std::vector<FrameFile> list_pattern_files(const std::string& pattern);

/// Files matching a glob such as "cache/cloth_*.obj", in natural order
/// ("f_9" before "f_10"). Throws InputError when nothing matches.
std::vector<FrameFile> list_glob_files(const std::string& glob);

/// The mesh files in a directory (all of one extension), in natural order.
/// Throws InputError when it holds none, or files of several mesh formats.
std::vector<FrameFile> list_directory_files(const std::string& directory);

}  // namespace snag::io
