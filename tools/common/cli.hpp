// Option handling shared by the tools: the inputs that name a cache, and the
// frame and sampling options, the same in every tool.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "io/open_cache.hpp"

namespace snag::tools {

/// Raw cache options as the command line gives them; to_cache_options() checks them.
struct CacheArguments {
  std::vector<std::string> inputs;      ///< positional: files, patterns, globs, directories
  std::vector<std::string> topologies;  ///< --topology, one per point cache, in order
  std::vector<std::string> names;       ///< --name, one per input, in order
  std::string frames;                   ///< --frames A:B[:S]
  bool sequence = false;                ///< --sequence: the inputs are the frames of one object
  double sample_rate = 0;               ///< --fps for animated files (0 = the file's own)
  double start_time = -1, end_time = -1;
  std::string weld;                     ///< --weld auto|none|exact|DIST; empty: not given (auto)
};

/// Adds the positional inputs and --topology, --name, --frames, --fps,
/// --start, --end, --weld to `app`.
void add_cache_options(CLI::App& app, CacheArguments& arguments);

/// Turns parsed arguments into io::CacheOptions. Point caches (.pc2, .mdd)
/// take the --topology values in order. Throws UsageError.
io::CacheOptions to_cache_options(const CacheArguments& arguments);

/// Parses argv; prints help or the CLI11 error and returns the exit code to
/// use when parsing ended the run (0 for --help/--version, 2 for errors), or -1
/// to go on.
int parse_command_line(CLI::App& app, int argc, char** argv);

}  // namespace snag::tools
