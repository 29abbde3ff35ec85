// Runs a built tool as a child process and captures what it says: standard
// output, standard error and the exit code. For the end-to-end tests.
#pragma once

#include <string>
#include <vector>

namespace snag::test {

/// What a finished child process left behind.
struct ProcessResult {
  int exit_code = -1;       ///< the exit status; 128 + N when killed by signal N
  std::string out, err;     ///< everything written to standard output and standard error
  bool timed_out = false;   ///< killed for running past ProcessOptions::timeout_seconds
  double seconds = 0;       ///< wall time from start to exit
};

/// Limits on a child process.
struct ProcessOptions {
  double timeout_seconds = 0;       ///< > 0: killed (SIGKILL) after this long, and timed_out set
  double signal_after_seconds = 0;  ///< > 0: sent `signal` after this long
  int signal = 2;                   ///< SIGINT
};

/// Runs `executable` with `arguments` (argv[1..]), standard input closed,
/// standard output and standard error captured in full, and waits for it.
/// Throws std::runtime_error when the process cannot be started.
ProcessResult run_process(const std::string& executable, const std::vector<std::string>& arguments,
                          const ProcessOptions& options = {});

/// The non-empty lines of `text`.
std::vector<std::string> lines_of(const std::string& text);

/// A fresh directory under the system's temporary directory, removed with
/// everything in it when the object is destroyed.
class TemporaryDirectory {
 public:
  TemporaryDirectory();
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  /// The directory's path joined with `name`.
  std::string path(const std::string& name = "") const;
  /// Writes `bytes` to the file `name` in the directory and returns its path.
  std::string write(const std::string& name, const std::string& bytes) const;

 private:
  std::string root_;
};

/// The whole content of a file. Throws std::runtime_error when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace snag::test
