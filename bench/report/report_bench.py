#!/usr/bin/env python3
"""The report's cost as a user meets it, through snag-scan, end to end.

1. Memory on a long cache: a synthetic cache (make_long_cache.py, 500 frames
   by default) scanned at 50, 200 and all frames with every event listed: the
   peak resident size of each run; and during the longest run the resident
   size sampled every 0.1 s (the largest in its first tenth, about its first
   50 frames, against the largest after it).
2. The report's share of the time on the 12-frame cloth-ball sequence (frames
   92 and 93 of the shared meshes, repeated), every event listed: the
   trailer's timing.report (rules, regions, tracks, writing, on a thread of
   its own beside the scan) and timing.report_wait (how long the scan waited
   for it: what the report adds to the user's wait) against the rest of
   timing.total, and the peak resident size.
3. Reading the reports back with the streaming reader (MB/s).

Times are of one machine and one run: compare ratios, not seconds.

    report_bench.py [--build DIR | --scan EXE --reader EXE] [--backend cpu|cuda]
                    [--meshes DIR] [--work DIR] [--frames N] [--json FILE]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run_scan(command, sample_every=None):
    """Runs snag-scan; returns (exit code, its peak RSS in MiB, samples [(s, MiB)])."""
    with tempfile.TemporaryFile(mode="w+") as err:
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=err)
        samples = []
        sampler = None
        if sample_every:
            start = time.monotonic()

            def sample():
                while process.poll() is None:
                    try:
                        with open(f"/proc/{process.pid}/status") as status:
                            for line in status:
                                if line.startswith("VmRSS:"):
                                    samples.append((time.monotonic() - start, int(line.split()[1]) / 1024))
                    except OSError:
                        pass
                    time.sleep(sample_every)

            sampler = threading.Thread(target=sample)
            sampler.start()
        # wait4: this child's own peak, not the largest of every child so far.
        _, status, usage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(status)
        if sampler:
            sampler.join()
        if process.returncode not in (0, 1):
            err.seek(0)
            sys.exit(f"report_bench: {' '.join(command)} failed ({process.returncode}): {err.read().strip()}")
    return process.returncode, usage.ru_maxrss / 1024, samples


def trailer(path):
    with open(path, "rb") as report:
        report.seek(max(0, os.path.getsize(path) - (1 << 20)))
        return json.loads(report.read().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--scan")
    parser.add_argument("--reader")
    parser.add_argument("--backend", default="cpu")
    parser.add_argument("--meshes", default=os.path.join(ROOT, "..", "shared", "data", "meshes"))
    parser.add_argument("--work")
    parser.add_argument("--frames", type=int, default=500)
    parser.add_argument("--json", help="also write the numbers here")
    args = parser.parse_args()
    scan = args.scan or os.path.join(args.build, "tools", "snag-scan")
    reader = args.reader or os.path.join(args.build, "bench", "report", "snag-bench-report-read")
    work = args.work or tempfile.mkdtemp(prefix="snag-report-bench-")
    os.makedirs(work, exist_ok=True)
    results = {"backend": args.backend, "long": [], "cloth_ball_12": {}, "read": []}

    print(f"== 1. memory on a long cache ({args.frames} frames, a 100 x 100 sheet over a floor), {args.backend}")
    long_dir = os.path.join(work, "long")
    subprocess.run([sys.executable, os.path.join(HERE, "make_long_cache.py"), long_dir, str(args.frames)], check=True)
    inputs = [os.path.join(long_dir, "sheet.pc2"), "-t", os.path.join(long_dir, "sheet.obj"),
              os.path.join(long_dir, "floor.pc2"), "-t", os.path.join(long_dir, "floor.obj")]
    print(f"{'frames':>8} {'peak MiB':>10} {'total s':>9} {'report s':>9} {'waited s':>9} {'waited %':>9} "
          f"{'events':>10} {'MB':>8}")
    for frames in sorted({min(50, args.frames), min(200, args.frames), args.frames}):
        path = os.path.join(work, f"long_{frames}.jsonl")
        longest = frames == args.frames
        _, peak, samples = run_scan([scan, *inputs, "-b", args.backend, "--frames", f"0:{frames - 1}",
                                     "--max-events", "0", "-q", "-r", path], 0.1 if longest else None)
        t = trailer(path)
        total, report, waited = t["timing"]["total"], t["timing"]["report"], t["timing"]["report_wait"]
        row = {"frames": frames, "peak_mib": peak, "total_s": total, "report_s": report, "waited_s": waited,
               "waited_share": waited / (total - waited), "events": t["summary"]["events"],
               "megabytes": os.path.getsize(path) / 1e6}
        results["long"].append(row)
        print(f"{frames:>8} {peak:>10.1f} {total:>9.2f} {report:>9.3f} {waited:>9.3f} "
              f"{100 * row['waited_share']:>8.1f}% {row['events']:>10} {row['megabytes']:>8.1f}")
        if longest and samples:
            end = samples[-1][0]
            early = max((mib for s, mib in samples if s <= 0.1 * end), default=0)
            late = max((mib for s, mib in samples if s > 0.1 * end), default=0)
            results["long_sampled"] = {"samples": len(samples), "seconds": end, "first_tenth_mib": early,
                                       "after_mib": late}
            print(f"  resident size, {len(samples)} samples over {end:.1f} s: largest in the first tenth "
                  f"{early:.1f} MiB, after it {late:.1f} MiB")

    print(f"== 2. the report's share: cloth-ball 92/93 as a 12-frame sequence, {args.backend}, every event listed")
    sequence = [os.path.join(args.meshes, f"cloth_ball9{k}.ply") for _ in range(6) for k in (2, 3)]
    path = os.path.join(work, "cloth_ball_12.jsonl")
    _, peak, _ = run_scan([scan, "--sequence", *sequence, "-b", args.backend, "--max-events", "0", "-q", "-r", path])
    t = trailer(path)
    total, report, waited = t["timing"]["total"], t["timing"]["report"], t["timing"]["report_wait"]
    results["cloth_ball_12"] = {"events": t["summary"]["events"], "total_s": total, "report_s": report,
                                "waited_s": waited, "waited_share": waited / (total - waited), "peak_mib": peak,
                                "megabytes": os.path.getsize(path) / 1e6}
    print(f"  {t['summary']['events']} events; scan {total:.2f} s; the report took {report:.3f} s beside it, "
          f"the scan waited {waited:.3f} s for it ({100 * waited / (total - waited):.1f}% of the rest); "
          f"peak {peak:.1f} MiB; report {os.path.getsize(path) / 1e6:.1f} MB")

    print("== 3. reading reports back (streaming reader, best of 3, file in the page cache)")
    if os.access(reader, os.X_OK):
        out = subprocess.run([reader, path, os.path.join(work, f"long_{args.frames}.jsonl")], check=True,
                             capture_output=True, text=True).stdout
        print(out, end="")
        results["read"] = out.splitlines()
    else:
        print(f"  ({reader} not built)")
    if args.json:
        with open(args.json, "w") as out:
            json.dump(results, out, indent=1)
    print(f"report_bench: files in {work}")


if __name__ == "__main__":
    main()
