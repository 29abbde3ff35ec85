// bench/gpu/trace_summary.py on hand-made device timelines (the CSV that
// libsnag_cupti_trace.so writes), whose busy and idle time, gaps, kernels and
// copies per step are known by construction; the host's calls in the same
// CSV are left out.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/tools/run_process.hpp"

namespace snag::test {
namespace {

constexpr const char* kMarker = "_ZN4snag12_GLOBAL__N_121ccd_early_exit_kernelINS0_13EdgeEdgeQueryEEEvT_m";
constexpr const char* kPairs = "_ZN4snag12_GLOBAL__N_121triangle_pairs_kernelEPKdm";

// `steps` steps of 1 ms each: the marker kernel for 100 us, then on another
// stream the pair kernel from 200 to 600 us and a 1 MB copy from 500 to
// 700 us (overlapping it). Busy 600 us a step; idle 400 us in two gaps, of
// 100 and 300 us.
std::string timeline(int steps) {
  std::string csv = "kind,start_ns,end_ns,stream,bytes,name\n";
  auto row = [&](const char* kind, long long start, long long end, int stream, long long bytes, const char* name) {
    csv += std::string(kind) + "," + std::to_string(start) + "," + std::to_string(end) + "," + std::to_string(stream) +
           "," + std::to_string(bytes) + "," + name + "\n";
  };
  for (int k = 0; k < steps; ++k) {
    const long long t = 5'000'000'000LL + k * 1'000'000LL;
    row("memcpy", t + 500'000, t + 700'000, 7, 1'000'000, "DtoH");  // out of order: the script sorts
    row("kernel", t, t + 100'000, 7, 0, kMarker);
    row("kernel", t + 200'000, t + 600'000, 9, 0, kPairs);
  }
  return csv;
}

ProcessResult summarize(const std::string& csv, const TemporaryDirectory& dir, std::vector<std::string> options = {}) {
  options.insert(options.begin(), TRACE_SUMMARY_PY);
  options.push_back(dir.write("trace.csv", csv));
  return run_process(SNAG_PYTHON3, options, {60});
}

TEST(TraceSummary, BusyIdleGapsKernelsAndCopiesPerStep) {
  TemporaryDirectory dir;
  const ProcessResult run = summarize(timeline(9), dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // Markers 2..6 of 9: four whole steps.
  EXPECT_NE(run.out.find("9 steps"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("measured over steps 2..6 (4)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("per step: 1.000 ms; device busy 0.600 ms, idle 0.400 ms"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("gaps of 5 us or more: 2.0 per step, 0.400 ms"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("longest gaps (ms): 0.300 0.300 0.300 0.300 0.100"), std::string::npos) << run.out;
  // Each 300 us gap follows the copy (which ends last) and comes before the next step's marker.
  EXPECT_NE(run.out.find("0.300 ms between [memcpy DtoH] and "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("0.300 ms between [memcpy DtoH] and the window end"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("kernels: 0.500 ms per step"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("memcpy DtoH: 1.00 MB, 0.200 ms per step"), std::string::npos) << run.out;
  for (const char* line :
       {"stream 7: 2.0 activities per step, busy 0.300 ms", "stream 9: 1.0 activities per step, busy 0.400 ms"})
    EXPECT_NE(run.out.find(line), std::string::npos) << line << "\n" << run.out;
  // Each stream's idle time and the work its gaps follow: on stream 7, 400
  // us after the marker and 300 after the copy (the last one up to the
  // window's end); on stream 9, 600 us after the pair kernel but at the
  // window's end (400) and 200 before its first launch.
  for (const char* line : {"busy 0.300 ms, idle 0.700 ms; 2.0 gaps of 5 us or more per step, 0.700 ms",
                           "after [memcpy DtoH]: 1.0 per step, 0.300 ms", "busy 0.400 ms, idle 0.600 ms;",
                           ": 1.0 per step, 0.550 ms", "after the window start: 0.2 per step, 0.050 ms"})
    EXPECT_NE(run.out.find(line), std::string::npos) << line << "\n" << run.out;
  const std::size_t stream7 = run.out.find("stream 7:");
  EXPECT_LT(run.out.find(": 1.0 per step, 0.400 ms", stream7), run.out.find("after [memcpy DtoH]", stream7))
      << run.out;  // the longest first
  // The pair kernel first (400 us a step), under its readable name when
  // c++filt is there, else its mangled one.
  const std::size_t pairs = run.out.find("0.400        1.0  ");
  ASSERT_NE(pairs, std::string::npos) << run.out;
  EXPECT_LT(pairs, run.out.find("0.100        1.0  ")) << run.out;
}

// --stream-waits 1: each stream's longest wait alone (stream 7's after the
// marker, 400 us a step, not the copy's 300).
TEST(TraceSummary, StreamWaitsListsTheLongestFirst) {
  TemporaryDirectory dir;
  const ProcessResult run = summarize(timeline(9), dir, {"--stream-waits", "1"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find(": 1.0 per step, 0.400 ms"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("after [memcpy DtoH]"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("after the window start"), std::string::npos) << run.out;
}

// A step that runs in three chunks launches the marker three times (at 0,
// 300 and 600 us of each 1 ms step, 100 us each): with --steps 9 its 27
// launches are nine steps of 1 ms, busy 300 us; without it each chunk counts
// as a step; launches that do not divide into the steps are an error.
TEST(TraceSummary, ChunkedStepsAreTakenWholeWithSteps) {
  TemporaryDirectory dir;
  std::string csv = "kind,start_ns,end_ns,stream,bytes,name\n";
  for (int k = 0; k < 9; ++k)
    for (int chunk = 0; chunk < 3; ++chunk) {
      const long long t = 5'000'000'000LL + k * 1'000'000LL + chunk * 300'000LL;
      csv += "kernel," + std::to_string(t) + "," + std::to_string(t + 100'000) + ",7,0," + kMarker + "\n";
    }
  const ProcessResult steps = summarize(csv, dir, {"--steps", "9"});
  ASSERT_EQ(steps.exit_code, 0) << steps.err;
  EXPECT_NE(steps.out.find("9 steps (marker /"), std::string::npos) << steps.out;
  EXPECT_NE(steps.out.find(", 3 launches a step), measured over steps 2..6 (4)"), std::string::npos) << steps.out;
  EXPECT_NE(steps.out.find("per step: 1.000 ms; device busy 0.300 ms, idle 0.700 ms"), std::string::npos) << steps.out;
  EXPECT_NE(steps.out.find("0.300        3.0  "), std::string::npos) << steps.out;
  const ProcessResult chunks = summarize(csv, dir);
  ASSERT_EQ(chunks.exit_code, 0) << chunks.err;
  EXPECT_NE(chunks.out.find("27 steps (marker /"), std::string::npos) << chunks.out;
  EXPECT_EQ(chunks.out.find("launches a step"), std::string::npos) << chunks.out;
  for (const char* wrong : {"10", "54", "0"}) {
    const ProcessResult run = summarize(csv, dir, {"--steps", wrong});
    EXPECT_NE(run.exit_code, 0) << wrong;
    EXPECT_NE(run.err.find("27 launches of the marker"), std::string::npos) << wrong << ": " << run.err;
  }
}

// The host's calls (SNAG_CUPTI_API=1) are not device work: a wait over each
// step's idle time and a launch beside it change nothing in the summary.
TEST(TraceSummary, HostCallsAreLeftOut) {
  TemporaryDirectory dir;
  std::string csv = timeline(9);
  for (int k = 0; k < 9; ++k) {
    const long long t = 5'000'000'000LL + k * 1'000'000LL;
    csv += "api," + std::to_string(t + 600'000) + "," + std::to_string(t + 1'000'000) + ",4242,77,cudaStreamSynchronize\n";
    csv += "api," + std::to_string(t + 10'000) + "," + std::to_string(t + 15'000) + ",4243,78,cudaLaunchKernel\n";
  }
  const ProcessResult plain = summarize(timeline(9), dir), with_calls = summarize(csv, dir);
  ASSERT_EQ(with_calls.exit_code, 0) << with_calls.err;
  EXPECT_EQ(with_calls.out, plain.out);
}

TEST(TraceSummary, TooFewStepsIsAnError) {
  TemporaryDirectory dir;
  const ProcessResult run = summarize(timeline(3), dir);
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("too few steps"), std::string::npos) << run.err;
  const ProcessResult empty = summarize("kind,start_ns,end_ns,stream,bytes,name\n", dir);
  EXPECT_NE(empty.exit_code, 0);
  EXPECT_NE(empty.err.find("lists no device work"), std::string::npos) << empty.err;
}

}  // namespace
}  // namespace snag::test
