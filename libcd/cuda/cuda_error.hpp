// The error type of the CUDA back end: a failed CUDA call or kernel launch.
// Plain C++, so that code which never includes CUDA headers (the tools) can
// catch it and report it (exit code 3, internal error).
#pragma once

#include <stdexcept>
#include <string>

namespace snag {

/// A CUDA runtime call or kernel launch failed.
/// what() is one line: "FILE:LINE: CALL failed: cudaErrorName (error string)".
class CudaError : public std::runtime_error {
 public:
  /// @param message  the full one-line message (what())
  /// @param code     the cudaError_t value, as an int
  CudaError(const std::string& message, int code) : std::runtime_error(message), code_(code) {}
  /// The cudaError_t value, as an int (CUDA types stay out of this header).
  int code() const { return code_; }

 private:
  int code_;
};

}  // namespace snag
