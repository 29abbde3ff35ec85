#!/usr/bin/env python3
"""snag-scan --backend cuda under device-memory limits: time per step, peak
device memory and whether the events are the same as the first run's.

One two-frame step (t0 t1) repeated as a --frames sequence (t0 t1 t0 ...);
the time per step is (total of the long run - total of the 2-frame run) /
(frames - 2), as bench/scan/scan_bench.py takes it. For each configuration
(an executable and a --device-memory value, "default" for none), the long
run's device memory is sampled with nvidia-smi (peak above what was in use
before) and its report's tracker peak (stages.*.peak_memory_bytes: the bytes
the back end's buffers held) is read; every event line of the long run is
compared with the first configuration's (--max-events 0). Last, a limit far
too small must end snag-scan with exit status 2 and one line on stderr.

    memory_limit_bench.py --scan EXE [--baseline EXE] --t0 PLY --t1 PLY
                          [--limits default,8G,4G] [--frames 12] [--runs 1] --work DIR [--json FILE]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "scan"))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "report"))
from report_bench import trailer  # noqa: E402
from scan_bench import event_digest, run_scan, stage_seconds  # noqa: E402


def measure(args, label, exe, limit):
    per_step, device_peaks, tracker_peak, digest = [], [], 0, None
    for run in range(args.runs):
        totals = {}
        for frames in (2, args.frames):
            path = os.path.join(args.work, f"{label}_{frames}.jsonl")
            sequence = [(args.t0, args.t1)[k % 2] for k in range(frames)]
            command = [exe, "--sequence", *sequence, "-b", "cuda", "-m", "all", "-q", "-r", path]
            if frames == args.frames and run == 0:
                command += ["--max-events", "0"]
            if limit != "default":
                command += ["--device-memory", limit]
            try:
                _, device, _ = run_scan(command, sample_device=frames == args.frames)
            except SystemExit as failure:  # run_scan exits on a failed scan: a row that says so
                return {"label": label, "limit": limit, "failed": str(failure)}
            t = trailer(path)
            totals[frames] = stage_seconds(t)["total"]
            if frames == args.frames:
                device_peaks.append(device)
                stages = t.get("stages", {})
                tracker_peak = max([tracker_peak] + [stages.get(k, {}).get("peak_memory_bytes", 0)
                                                     for k in ("ccd_broad_phase", "static_broad_phase")])
                if run == 0:
                    digest = event_digest(path)
        per_step.append(1e3 * (totals[args.frames] - totals[2]) / (args.frames - 2))
    return {"label": label, "limit": limit, "ms_per_step": statistics.median(per_step),
            "spread_ms": [min(per_step), max(per_step)],
            "device_peak_mib": max((d for d in device_peaks if d is not None), default=None),
            "tracker_peak_mib": tracker_peak / 2**20, "events": digest[0], "digest": digest[1][:16]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scan", required=True)
    parser.add_argument("--baseline", help="another snag-scan (no --device-memory) measured first")
    parser.add_argument("--t0", required=True)
    parser.add_argument("--t1", required=True)
    parser.add_argument("--limits", default="default,8G,4G")
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--work", required=True)
    parser.add_argument("--json")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)

    # Each row is printed as soon as it is measured (a run cut short keeps what it printed).
    configurations = [("baseline", args.baseline, "default")] if args.baseline else []
    configurations += [(f"limit_{limit}", args.scan, limit) for limit in args.limits.split(",")]
    print(f"{'run':18} {'limit':>8} {'ms/step':>9} {'spread':>17} {'device MiB':>11} {'buffers MiB':>12} "
          f"{'events':>9}  same events as {configurations[0][0]}", flush=True)
    rows, reference = [], None
    for label, exe, limit in configurations:
        r = measure(args, label, exe, limit)
        rows.append(r)
        if reference is None:
            reference = r.get("digest")
        r["same_events"] = r.get("digest") == reference
        if "failed" in r:
            print(f"{r['label']:18} {r['limit']:>8} failed: {r['failed']}")
            continue
        device = f"{r['device_peak_mib']:.0f}" if r["device_peak_mib"] is not None else "-"
        print(f"{r['label']:18} {r['limit']:>8} {r['ms_per_step']:9.1f} "
              f"{r['spread_ms'][0]:8.1f}-{r['spread_ms'][1]:<8.1f} {device:>11} {r['tracker_peak_mib']:12.0f} "
              f"{r['events']:9d}  {'yes' if r['same_events'] else 'NO'}", flush=True)

    # A limit far too small: exit status 2 and one line.
    small = subprocess.run([args.scan, "--sequence", args.t0, args.t1, "-b", "cuda", "-q", "--device-memory", "1M",
                            "-r", os.path.join(args.work, "small.jsonl")], capture_output=True, text=True)
    lines = small.stderr.strip().splitlines()
    small_ok = small.returncode == 2 and len(lines) == 1
    print(f"--device-memory 1M: exit {small.returncode}, {len(lines)} line(s): {small.stderr.strip()}")
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"rows": rows, "too_small": {"exit": small.returncode, "stderr": small.stderr.strip(),
                                                   "ok": small_ok}}, out, indent=1)
    return 0 if small_ok and all(r["same_events"] or "failed" in r for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
