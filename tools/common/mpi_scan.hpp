// snag-scan over MPI: rank r scans the r-th range of steps (range_scan.hpp)
// on the GPU its local rank picks, or on the CPU, digests its frames (rules
// and regions) and stores the digests in a part (report/scan_part.hpp); rank
// 0 scans the first range straight into the report's sink, then joins the
// other parts in order into it (region ids, tracks, the event cap, totals),
// so that one report comes out, identical to one process's but for the
// times. Rank 0 joins a part while its rank still writes it, and scans a
// smaller range than the others (split_steps' merge cost) to make time for that.
//
// Failure: a rank that throws tells rank 0 (its exit code and message);
// rank 0 stops the others, removes the parts and the unfinished report, and
// the run exits with that code and one line naming the rank. Only the
// main thread of each rank calls MPI. Built only with SNAG_WITH_MPI.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "libcd/pipeline/scan.hpp"
#include "report/scan_part.hpp"
#include "tools/common/range_scan.hpp"

namespace snag::tools::mpi {

/// Whether this process was started by mpirun (Open MPI's or a PMI launcher's).
bool launched_by_mpirun();

/// cli.hpp's parse_command_line() on every rank, before MPI starts: ranks
/// other than 0 (as the launcher says) print nothing, so that a usage error
/// or --help comes once, not once per rank.
int parse_command_line_on_every_rank(CLI::App& app, int argc, char** argv);

/// The run's ranks, and the messages that end them. Made once per process:
/// initialises MPI and finalises it when destroyed.
class Run {
 public:
  Run(int* argc, char*** argv);
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Rank among the ranks of this host (picks the GPU).
  int local_rank() const { return local_rank_; }

  /// Runs `body` on every rank and returns this process's exit code: rank
  /// 0's result, or the failing rank's code with its message printed as
  /// "TOOL: error: rank R: ..." (others return 0 and print nothing; what
  /// their body returned reaches rank 0 through wait_for_everyone()).
  /// `parts_near`: a file whose directory holds the parts (the report: on
  /// several hosts it must be shared; "-": the working directory); empty:
  /// the run makes no parts.
  int run(const char* tool, const std::string& parts_near, const std::function<int()>& body);

  /// The ranges of a scan of `frame_count` frames over this run's ranks:
  /// split_steps() at rank 0's merge cost on back end `backend` (its name),
  /// SNAG_MPI_MERGE_COST when set where rank 0 runs (a number in [0, 0.9];
  /// else UsageError; rank 0's value is every rank's), a collective call,
  /// else the cost measured on that back end (man snag-scan(1)).
  std::vector<StepRange> split(std::size_t frame_count, const std::string& backend) const;

  /// Ranks > 0: scans this rank's range of `ranges` (split_steps over
  /// size()) into its part, re-deciding each step's events with
  /// `redecide` and digesting each frame under `rules` and `report`'s
  /// listing (report/scan_part.hpp); stops (throws) when rank 0 says so.
  void scan_part(const FrameSource& source, const std::vector<StepRange>& ranges, Backend& backend,
                 const ScanSettings& settings, const report::RuleSet& rules, const report::ReportSettings& report,
                 report::PartRedecide redecide);

  /// What rank 0 passes to the report's trailer.
  struct Totals {
    std::string stages_json, timing_json;
    double total_seconds = 0;
  };
  /// Rank 0: scans the first of `ranges` into `sink`, then joins each other
  /// rank's part in rank order, following it while its rank writes it. With other
  /// ranks, the timing gets "after_last_rank": rank 0's seconds from the
  /// last other rank's end to its own. Throws what it or a rank threw.
  Totals scan_and_merge(const FrameSource& source, const std::vector<StepRange>& ranges, Backend& backend,
                        const ScanSettings& settings, report::ReportSink& sink, const ProgressCallback& progress);

  /// Rank 0: waits until every other rank has finished and returns the
  /// largest of their exit codes. Throws when one failed.
  int wait_for_everyone();

 private:
  std::string part_path(int rank) const;
  void poll_messages();
  void wait_for(int rank);
  void receive_done();
  void stop_everyone();

  int rank_ = 0, size_ = 1, local_rank_ = 0;
  std::string parts_dir_;
  std::vector<int> done_;        // rank 0: how each rank ended (Ending in mpi_scan.cpp)
  std::vector<int> codes_;       // rank 0: each finished rank's exit code
  std::vector<std::chrono::steady_clock::time_point> finished_at_;  // rank 0: when each rank said it was done
  bool stop_received_ = false;   // ranks > 0: rank 0 said stop (or end)
};

}  // namespace snag::tools::mpi
