#!/usr/bin/env python3
"""Where a step's device time goes: reads a CSV that libsnag_cupti_trace.so
wrote (bench/gpu/cupti_trace.cpp) and prints, per step, the time the device
was busy (any kernel, copy or memset running, on any stream) and idle, the
gaps between device work, each stream's busy and idle time with the work
its gaps follow, and the kernels' and copies' totals.

A step is the time from one launch of a marker kernel to the next (default:
the edge-edge CCD early-exit kernel, launched once per step and chunk); with
--steps N, the time from one step's first launch to the next step's, the
launches taken launches / N at a time (a scene whose steps run in chunks:
without it each chunk counts as a step). The figures cover the middle half
of the steps, away from the scan's start and end. Example:

  CUDA_INJECTION64_PATH=build/bench/gpu/libsnag_cupti_trace.so \\
  SNAG_CUPTI_TRACE=trace.csv snag-scan --sequence f0.ply f1.ply ... f11.ply -b cuda -q
  bench/gpu/trace_summary.py --steps 11 trace.csv
"""
import argparse
import csv
import re
import shutil
import subprocess
import sys
from collections import defaultdict


def demangle(names):
    """Readable kernel names (c++filt when installed), shortened to the
    function's name and its first template argument."""
    names = list(names)
    readable = names
    if shutil.which("c++filt"):
        out = subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True).stdout
        lines = out.splitlines()
        if len(lines) == len(names):
            readable = lines
    short = {}
    for mangled, name in zip(names, readable):
        short[mangled] = shorten(name)[:70]
    return short


def matching(text, at, opening, closing, step):
    """Index of the bracket that closes (step 1) or opens (step -1) the one at `at`."""
    depth = 0
    while 0 <= at < len(text):
        depth += (text[at] == opening) - (text[at] == closing)
        if depth == 0:
            return at
        at += step
    return -1


def shorten(name):
    """'void snag::(anonymous namespace)::kernel<snag::Query, 3>(args)' -> 'kernel<Query>'."""
    name = name.replace("(anonymous namespace)::", "")
    if name.endswith(")"):  # the parameters
        opened = matching(name, len(name) - 1, ")", "(", -1)
        if opened > 0:
            name = name[:opened]
    if name.startswith("void "):
        name = name[5:]
    angle = name.find("<")
    if angle < 0:
        return name.split("::")[-1]
    close = matching(name, angle, "<", ">", 1)
    arguments = name[angle + 1:close if close > 0 else len(name)]
    depth, first = 0, ""
    for c in arguments:  # the first template argument, at the top level
        depth += (c == "<") - (c == ">")
        if c == "," and depth == 0:
            break
        first += c
    first = re.sub(r"<.*", "", first.strip()).split("::")[-1]
    return f"{name[:angle].split('::')[-1]}<{first}>"


def union_length(intervals, lo, hi):
    """Total length of the union of [start, end) intervals (with a label
    after them, if any) clipped to [lo, hi), and the gaps between them:
    (length, label of the work that ended last before it, label of the work
    after it)."""
    covered, gaps, reach, last = 0, [], lo, None
    for start, end, *label in sorted(intervals):
        label = label[0] if label else None
        start, end = max(start, lo), min(end, hi)
        if end <= start:
            continue
        if start > reach:
            gaps.append((start - reach, last, label))
        if end > reach:
            covered += end - max(start, reach)
            reach, last = end, label
    if hi > reach:
        gaps.append((hi - reach, last, None))
    return covered, gaps


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("trace", help="CSV written by libsnag_cupti_trace.so")
    parser.add_argument("--marker", default="ccd_early_exit_kernel.*EdgeEdgeQuery",
                        help="regular expression on the mangled kernel name that starts a step")
    parser.add_argument("--steps", type=int,
                        help="the steps the trace holds (the scan's frames less one): where a step runs in chunks "
                        "(a large scene, --device-memory), the marker runs once a chunk, and its launches are "
                        "taken launches / steps at a time (the same number every step)")
    parser.add_argument("--gap", type=float, default=5.0, help="gaps shorter than this many microseconds are not listed")
    parser.add_argument("--kernels", type=int, default=15, help="kernels listed")
    parser.add_argument("--gap-context", type=int, default=5,
                        help="longest gaps listed with the work before and after them")
    parser.add_argument("--stream-waits", type=int, default=3,
                        help="for each stream, the works after which its gaps are longest, listed")
    args = parser.parse_args()

    rows = []
    with open(args.trace, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "api":  # the host's calls (SNAG_CUPTI_API=1): not device work
                continue
            rows.append((row["kind"], int(row["start_ns"]), int(row["end_ns"]), row["stream"], int(row["bytes"]),
                         row["name"]))
    if not rows:
        sys.exit(f"trace_summary: {args.trace} lists no device work")
    marker = re.compile(args.marker)
    launches = sorted(r[1] for r in rows if r[0] == "kernel" and marker.search(r[5]))
    per_step = 1
    if args.steps is not None:
        if args.steps < 1 or len(launches) < args.steps or len(launches) % args.steps != 0:
            sys.exit(f"trace_summary: {len(launches)} launches of the marker /{args.marker}/ do not divide into "
                     f"{args.steps} steps (the same number each)")
        per_step = len(launches) // args.steps
    starts = launches[::per_step]
    if len(starts) < 5:
        sys.exit(f"trace_summary: {len(starts)} steps (marker /{args.marker}/): too few steps to measure")
    first, last = len(starts) // 4, 3 * len(starts) // 4
    lo, hi = starts[first], starts[last]
    steps = last - first
    ms = 1e-6 / steps  # ns in the window -> ms per step

    names = demangle({r[5] for r in rows if r[0] == "kernel"})

    def label(r):
        return names.get(r[5], r[5]) if r[0] == "kernel" else f"[{r[0]} {r[5]}]"

    busy, gap_list = union_length([(r[1], r[2], label(r)) for r in rows], lo, hi)
    gaps = [g[0] for g in gap_list]
    listed = sorted((g for g in gaps if g >= args.gap * 1e3), reverse=True)
    each = f", {per_step} launches a step" if per_step > 1 else ""
    print(f"trace: {len(rows)} activities; {len(starts)} steps (marker /{args.marker}/{each}), "
          f"measured over steps {first}..{last} ({steps})")
    print(f"per step: {(hi - lo) * ms:.3f} ms; device busy {busy * ms:.3f} ms, idle {(hi - lo - busy) * ms:.3f} ms")
    print(f"  gaps of {args.gap:g} us or more: {len(listed) / steps:.1f} per step, {sum(listed) * ms:.3f} ms; "
          f"shorter: {(len(gaps) - len(listed)) / steps:.1f} per step, {(hi - lo - busy - sum(listed)) * ms:.3f} ms")
    print("  longest gaps (ms): " + " ".join(f"{g * 1e-6:.3f}" for g in listed[:8]))
    for length, before, after in sorted(gap_list, key=lambda g: -g[0])[:args.gap_context]:
        print(f"    {length * 1e-6:.3f} ms between {before or 'the window start'} and {after or 'the window end'}")

    # Each stream's busy time, and its idle time in gaps of --gap or more,
    # by the work each gap follows: a stream that waits after the same work
    # every step waits for the host there (a read back, a synchronization).
    in_window = [r for r in rows if lo <= r[1] < hi]
    streams = defaultdict(list)
    for r in in_window:
        streams[r[3]].append((r[1], r[2], label(r)))
    for stream, intervals in sorted(streams.items(), key=lambda item: -len(item[1])):
        stream_busy, stream_gaps = union_length(intervals, lo, hi)
        waits = [g for g in stream_gaps if g[0] >= args.gap * 1e3]
        print(f"  stream {stream}: {len(intervals) / steps:.1f} activities per step, busy {stream_busy * ms:.3f} ms, "
              f"idle {(hi - lo - stream_busy) * ms:.3f} ms; {len(waits) / steps:.1f} gaps of {args.gap:g} us or more "
              f"per step, {sum(g[0] for g in waits) * ms:.3f} ms")
        after = defaultdict(lambda: [0, 0])
        for length, before, _ in waits:
            entry = after[before or "the window start"]
            entry[0] += length
            entry[1] += 1
        for name, (length, count) in sorted(after.items(), key=lambda item: -item[1][0])[:args.stream_waits]:
            print(f"    after {name}: {count / steps:.1f} per step, {length * ms:.3f} ms")

    totals = defaultdict(lambda: [0, 0])
    for r in in_window:
        key = label(r)
        totals[key][0] += r[2] - r[1]
        totals[key][1] += 1
    kernel_time = sum(t for key, (t, _) in totals.items() if not key.startswith("["))
    print(f"kernels: {kernel_time * ms:.3f} ms per step (summed over streams)")
    print(f"  {'ms/step':>8} {'calls/step':>10}  name")
    for key, (time, calls) in sorted(totals.items(), key=lambda item: -item[1][0])[:args.kernels]:
        print(f"  {time * ms:8.3f} {calls / steps:10.1f}  {key}")
    copies = defaultdict(lambda: [0, 0])
    for r in in_window:
        if r[0] != "kernel":
            copies[f"{r[0]} {r[5]}"][0] += r[4]
            copies[f"{r[0]} {r[5]}"][1] += r[2] - r[1]
    for key, (size, time) in sorted(copies.items()):
        print(f"  {key}: {size / steps / 1e6:.2f} MB, {time * ms:.3f} ms per step")


if __name__ == "__main__":
    main()
