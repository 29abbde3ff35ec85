#include "tools/common/run_tool.hpp"

#include <cstdio>
#include <exception>
#include <new>

#include "libcd/core/error.hpp"

namespace snag::tools {

int run_tool(const char* tool_name, const std::function<int()>& body) {
  try {
    return body();
  } catch (const InputError& error) {
    std::fprintf(stderr, "%s: error: %s\n", tool_name, error.what());
    return kExitBadInput;
  } catch (const UsageError& error) {
    std::fprintf(stderr, "%s: error: %s\n", tool_name, error.what());
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: internal error: out of memory\n", tool_name);
    return kExitInternal;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s: internal error: %s\n", tool_name, error.what());
    return kExitInternal;
  } catch (...) {
    std::fprintf(stderr, "%s: internal error: unknown exception\n", tool_name);
    return kExitInternal;
  }
}

}  // namespace snag::tools
