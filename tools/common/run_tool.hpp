// The frame every tool's main runs in: catches everything, prints one clear
// line on standard error, and returns the documented exit code.
#pragma once

#include <functional>

namespace snag::tools {

/// Exit codes shared by every tool (PRODUCT.md).
enum ExitCode : int {
  kExitClean = 0,     ///< nothing found (or nothing over the threshold)
  kExitFound = 1,     ///< events at or over --fail-on, or verification failures
  kExitBadInput = 2,  ///< bad usage or bad input
  kExitInternal = 3,  ///< internal error
};

/// Runs `body` and maps exceptions to exit codes: snag::InputError and
/// snag::UsageError to 2, anything else to 3, each with one line
/// "TOOL: error: ..." on standard error.
int run_tool(const char* tool_name, const std::function<int()>& body);

}  // namespace snag::tools
