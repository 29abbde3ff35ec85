// An output file that replaces its destination only when complete: written to
// a temporary file beside it and renamed over it at the end. Until then an
// earlier file at the destination is untouched, whatever happens to the run:
// an exception, SIGINT or SIGTERM removes the temporary file. A destination
// that is a symbolic link has its target replaced; one that is not a regular
// file (a device such as /dev/null, a pipe, a socket) is written in place.
#pragma once

#include <fstream>
#include <string>

namespace snag::tools {

class ReplacingFile {
 public:
  /// Creates the temporary file ".NAME.XXXXXX" in the destination's
  /// directory. Throws UsageError naming `path` when it cannot. One
  /// ReplacingFile exists at a time (its signal handlers are process-wide).
  explicit ReplacingFile(const std::string& path);
  /// Removes the temporary file unless commit() renamed it.
  ~ReplacingFile();
  ReplacingFile(const ReplacingFile&) = delete;
  ReplacingFile& operator=(const ReplacingFile&) = delete;

  /// Where to write the content.
  std::ostream& stream() { return out_; }
  /// Flushes, closes, and renames the temporary file to the destination (with
  /// an earlier file's permissions, else 0666 less the umask). Throws
  /// UsageError naming the destination when writing or renaming failed.
  void commit();

 private:
  std::string path_, temporary_;
  std::ofstream out_;
  bool committed_ = false;
  bool in_place_ = false;  ///< written straight to a destination that is not a regular file
};

}  // namespace snag::tools
