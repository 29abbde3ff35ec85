#include "tools/common/mpi_scan.hpp"

#include <fcntl.h>
#include <mpi.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <thread>

#include <nlohmann/json.hpp>

#include "libcd/core/error.hpp"
#include "snag/config.hpp"
#include "tools/common/cli.hpp"
#include "tools/common/run_tool.hpp"
#include "tools/common/scan_stats.hpp"
#include "tools/common/stages_merge.hpp"
#if SNAG_HAVE_CUDA
#include <cuda_runtime_api.h>
#endif

namespace snag::tools::mpi {

namespace {

// A rank > 0 tells rank 0 once that it is done: how it ended, its exit code
// and, when it failed, its message. Rank 0 tells each rank > 0 once that the
// run ends (before it is done: stop).
constexpr int kTagDone = 1;
constexpr int kTagEnd = 2;
enum Ending : int { kNotYet = -1, kFinished = 0, kFailed = 1, kStopped = 2 };

// Rank 0's merge time per frame over a rank's scan time per frame (Run::split).
// CUDA: rank 0's join of digested parts measured 0.030-0.035 on two H200s
// (the trailer's timing.join over the one process's time per frame).
constexpr double kCpuMergeCost = 0.02;
constexpr double kCudaMergeCost = 0.03;

// Rank 0 learnt that another rank failed.
struct RankFailed {
  int rank, code;
  std::string message;
};

// A rank > 0 was told to stop.
struct Stopped {};

struct Failure {
  int code;
  std::string message;
};

// The exit code and line run_tool() would give for the exception in flight.
Failure describe_current_exception() {
  try {
    throw;
  } catch (const InputError& error) {
    return {kExitBadInput, error.what()};
  } catch (const UsageError& error) {
    return {kExitBadInput, error.what()};
  } catch (const std::bad_alloc&) {
    return {kExitInternal, "internal error: out of memory"};
  } catch (const std::exception& error) {
    return {kExitInternal, std::string("internal error: ") + error.what()};
  } catch (...) {
    return {kExitInternal, "internal error: unknown exception"};
  }
}

// Rank 0: a fresh directory beside `near` for the parts; "" and `error` set when it cannot be made.
std::string make_parts_dir(const std::string& near, std::string& error) {
  namespace fs = std::filesystem;
  fs::path dir = near == "-" ? fs::path(".") : fs::path(near).parent_path();
  if (dir.empty()) dir = ".";
  std::string name = (dir / ".snag-scan-parts.XXXXXX").string();
  if (!mkdtemp(name.data())) {
    error = dir.string() + ": cannot make a directory for the ranks' parts: " + std::strerror(errno);
    return "";
  }
  return fs::absolute(name).string();
}

void broadcast(std::string& text) {
  unsigned long long size = text.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  text.resize(size);
  MPI_Bcast(text.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD);
}

// The GPU of this rank: its local rank among the host's devices. Before the
// back end is chosen, which initialises CUDA on the current device.
void use_local_device(int local_rank) {
#if SNAG_HAVE_CUDA
  int count = 0;
  if (cudaGetDeviceCount(&count) == cudaSuccess && count > 0) cudaSetDevice(local_rank % count);
#else
  (void)local_rank;
#endif
}

}  // namespace

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name)) return true;
  }
  return false;
}

int parse_command_line_on_every_rank(CLI::App& app, int argc, char** argv) {
  bool other_rank = false;
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) {
    if (const char* rank = std::getenv(name)) {
      other_rank = std::strcmp(rank, "0") != 0;
      break;
    }
  }
  if (!other_rank) return parse_command_line(app, argc, argv);
  std::fflush(stdout);
  std::fflush(stderr);
  const int out = dup(STDOUT_FILENO), err = dup(STDERR_FILENO), null = open("/dev/null", O_WRONLY);
  dup2(null, STDOUT_FILENO);
  dup2(null, STDERR_FILENO);
  const int code = parse_command_line(app, argc, argv);
  std::fflush(stdout);
  std::fflush(stderr);
  dup2(out, STDOUT_FILENO);
  dup2(err, STDERR_FILENO);
  for (int fd : {out, err, null}) close(fd);
  return code;
}

Run::Run(int* argc, char*** argv) {
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm host;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &host);
  MPI_Comm_rank(host, &local_rank_);
  MPI_Comm_free(&host);
  use_local_device(local_rank_);
}

Run::~Run() { MPI_Finalize(); }

std::string Run::part_path(int rank) const { return parts_dir_ + "/part-" + std::to_string(rank); }

int Run::run(const char* tool, const std::string& parts_near, const std::function<int()>& body) {
  if (!parts_near.empty()) {
    std::string error;
    if (rank_ == 0) parts_dir_ = make_parts_dir(parts_near, error);
    broadcast(parts_dir_);
    if (parts_dir_.empty()) {  // rank 0 could not make it
      if (rank_ == 0) std::fprintf(stderr, "%s: error: rank 0: %s\n", tool, error.c_str());
      return rank_ == 0 ? kExitBadInput : kExitClean;
    }
  }
  if (rank_ != 0) {
    int ending = kFinished;
    Failure result{kExitClean, ""};
    try {
      result.code = body();
    } catch (const Stopped&) {
      ending = kStopped;
    } catch (...) {
      ending = kFailed;
      result = describe_current_exception();
    }
    const int head[2] = {ending, result.code};
    std::string message(sizeof head, '\0');
    std::memcpy(message.data(), head, sizeof head);
    message += result.message;
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_CHAR, 0, kTagDone, MPI_COMM_WORLD);
    if (!stop_received_) MPI_Recv(nullptr, 0, MPI_CHAR, 0, kTagEnd, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return kExitClean;
  }

  done_.assign(size_, kNotYet);
  codes_.assign(size_, kExitClean);
  finished_at_.assign(size_, std::chrono::steady_clock::time_point{});
  done_[0] = kFinished;
  int code = kExitClean, failed_rank = 0;
  std::string failure;
  try {
    code = body();
  } catch (const RankFailed& failed) {
    failed_rank = failed.rank;
    code = failed.code;
    failure = failed.message;
  } catch (...) {
    const Failure own = describe_current_exception();
    code = own.code;
    failure = own.message;
  }
  stop_everyone();
  std::error_code ignored;
  if (!parts_dir_.empty()) std::filesystem::remove_all(parts_dir_, ignored);
  if (!failure.empty()) std::fprintf(stderr, "%s: error: rank %d: %s\n", tool, failed_rank, failure.c_str());
  return code;
}

void Run::receive_done() {
  MPI_Status status;
  MPI_Probe(MPI_ANY_SOURCE, kTagDone, MPI_COMM_WORLD, &status);
  int size = 0;
  MPI_Get_count(&status, MPI_CHAR, &size);
  std::string message(static_cast<std::size_t>(size), '\0');
  MPI_Recv(message.data(), size, MPI_CHAR, status.MPI_SOURCE, kTagDone, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  int head[2] = {kFailed, kExitInternal};
  if (message.size() >= sizeof head) std::memcpy(head, message.data(), sizeof head);
  const int rank = status.MPI_SOURCE;
  finished_at_[rank] = std::chrono::steady_clock::now();
  done_[rank] = head[0];
  codes_[rank] = head[1];
  if (head[0] == kFailed) throw RankFailed{rank, head[1], message.substr(std::min(message.size(), sizeof head))};
}

int Run::wait_for_everyone() {
  int code = kExitClean;
  for (int r = 1; r < size_; ++r) {
    wait_for(r);
    code = std::max(code, codes_[r]);
  }
  return code;
}

void Run::poll_messages() {
  if (rank_ == 0) {
    int waiting = 1;
    while (waiting) {
      MPI_Iprobe(MPI_ANY_SOURCE, kTagDone, MPI_COMM_WORLD, &waiting, MPI_STATUS_IGNORE);
      if (waiting) receive_done();
    }
    return;
  }
  int waiting = 0;
  MPI_Iprobe(0, kTagEnd, MPI_COMM_WORLD, &waiting, MPI_STATUS_IGNORE);
  if (!waiting) return;
  MPI_Recv(nullptr, 0, MPI_CHAR, 0, kTagEnd, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  stop_received_ = true;
  throw Stopped{};
}

void Run::wait_for(int rank) {
  while (done_[rank] == kNotYet) receive_done();
}

void Run::stop_everyone() {
  for (int r = 1; r < size_; ++r) MPI_Send(nullptr, 0, MPI_CHAR, r, kTagEnd, MPI_COMM_WORLD);
  for (int r = 1; r < size_; ++r) {
    while (done_[r] == kNotYet) {
      try {
        receive_done();
      } catch (const RankFailed&) {
        // The run already failed: the first failure is the one reported.
      }
    }
  }
}

std::vector<StepRange> Run::split(std::size_t frame_count, const std::string& backend) const {
  // Rank 0's time to merge a frame of a part over a rank's time to scan it,
  // measured on the long cloth (scripts/mpi-scaling.sh; man snag-scan(1)).
  // Rank 0's setting is every rank's: ranks that split differently would
  // leave steps out or scan them twice (mpirun need not pass the variable on).
  const char* set_here = rank_ == 0 ? std::getenv("SNAG_MPI_MERGE_COST") : nullptr;
  std::string given = set_here ? std::string("=") + set_here : std::string();
  broadcast(given);
  double merge_cost = backend == "cuda" ? kCudaMergeCost : kCpuMergeCost;
  if (!given.empty()) {
    const char* text = given.c_str() + 1;
    char* end = nullptr;
    merge_cost = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(merge_cost >= 0 && merge_cost <= 0.9)) {
      throw UsageError(std::string("SNAG_MPI_MERGE_COST: expected a number from 0 to 0.9, not '") + text + "'");
    }
  }
  return split_steps(frame_count, static_cast<std::size_t>(size_), merge_cost);
}

void Run::scan_part(const FrameSource& source, const std::vector<StepRange>& ranges, Backend& backend,
                    const ScanSettings& settings, const report::RuleSet& rules,
                    const report::ReportSettings& report, report::PartRedecide redecide) {
  report::PartWriter part(part_path(rank_), source.scene(), rules, report, std::move(redecide));
  const ScanTotals totals =
      scan_range(source, ranges[rank_], backend, settings, part, [this](std::size_t, std::size_t) { poll_messages(); });
  poll_messages();
  part.finish({totals.frames, stages_json(totals), timing_json(totals)});
}

Run::Totals Run::scan_and_merge(const FrameSource& source, const std::vector<StepRange>& ranges, Backend& backend,
                                const ScanSettings& settings, report::ReportSink& sink,
                                const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t frame_count = source.frame_count();
  const ScanTotals own = scan_range(source, ranges[0], backend, settings, sink, [&](std::size_t done, std::size_t) {
    poll_messages();
    if (progress) progress(done, frame_count);
  });
  std::vector<std::string> stages, timing;
  double join_seconds = 0;
  std::size_t joined_frames = 0;
  if (!ranges[0].empty) {
    stages.push_back(stages_json(own));
    timing.push_back(timing_json(own));
  }
  // Each part is merged while its rank still writes it: rank 0 follows the
  // rank's frames as they come, and only what is left of the last part when
  // its rank finishes comes after the scan.
  for (int r = 1; r < size_; ++r) {
    auto wait_for_writer = [this, r] {
      poll_messages();  // throws when a rank failed
      if (done_[r] == kNotYet) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        poll_messages();
      }
      return done_[r] != kNotYet;
    };
    const report::PartTotals part = report::replay_part(
        part_path(r), source, sink,
        [&](std::size_t position) {
          poll_messages();
          if (progress) progress(position + 1, frame_count);
        },
        wait_for_writer);
    wait_for(r);
    join_seconds += part.join_seconds;
    joined_frames += part.frames;
    std::filesystem::remove(part_path(r));
    if (ranges[r].empty) continue;
    stages.push_back(part.stages_json);
    timing.push_back(part.timing_json);
  }
  Totals totals;
  const auto end = std::chrono::steady_clock::now();
  totals.total_seconds = std::chrono::duration<double>(end - start).count();
  // What the split leaves rank 0 to do once the other ranks are done: the
  // measure of how well its merge overlaps their scans.
  auto last_rank_end = start;
  for (int r = 1; r < size_; ++r) last_rank_end = std::max(last_rank_end, finished_at_[r]);
  if (stages.empty()) {  // no frames at all: what a scan of nothing writes
    const ScanTotals nothing;
    stages.push_back(stages_json(nothing));
    timing.push_back(timing_json(nothing));
  }
  totals.stages_json = merge_stages_json(stages);
  nlohmann::json timing_object = nlohmann::json::parse(merge_timing_json(timing, totals.total_seconds));
  if (size_ > 1) {
    timing_object["after_last_rank"] = std::chrono::duration<double>(end - last_rank_end).count();
    // Rank 0's time joining the other ranks' frames: over their scan time per frame, its merge cost.
    timing_object["join"] = join_seconds;
    timing_object["joined_frames"] = joined_frames;
  }
  totals.timing_json = timing_object.dump();
  return totals;
}

}  // namespace snag::tools::mpi
