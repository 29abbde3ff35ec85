#!/usr/bin/env python3
"""What the user waits for: snag-scan over a long sequence, per scene, per
stage and in total, with the back end's own share beside it and memory.

Each scene runs as a short (--short-frames, 2 by default) and a long
(--frames, 12 by default) selection of the same step repeated (t0 t1 t0 t1
...); the time per step is (long total - short total) / (long frames - short
frames), which leaves out what happens once (reading the topology, binding
the back end, starting the device). With a short selection of a few frames
(--short-frames 12 --frames 32) it leaves out the first frames' own costs
too (the digesters' first use, the report's listing of the first events,
the queue to the report filling): what a step costs once the scan runs. The
same difference is taken for every stage the report's trailer times
(timing.*): reading, the broad phases, the CCD narrow phase (hits, the host's
search of the undecided ones, events), certification, static detection, and
the time the scan waited for the report ("report" is the report's own time,
on a thread of its own beside the scan); "other" is the rest of the total
(reading and the report, on threads of their own, are not taken from it)
(per-step host work in the scan loop, ordering the frame's events, uploads the
scan waited for). "back end" is the sum of the back end's stages: what a
benchmark of the back end alone measures, from the same run.

What the user waits for in all: "wall" is the long run's whole time, from
starting snag-scan to its exit, and "outside" the part of it the report's
timing.total leaves out (opening the cache and reading its topology,
starting the device and binding the back end, writing the report's end,
exiting), in ms, which the time per step does not show; "start" is the part
before the scan (the report's timing.start). "N-fr ms" is the short run's
timing.total: the time per step is a difference of two runs, so that a
change to what the first frames cost moves it too (a slower 2-frame run
makes the step look faster); the two are read together.

Memory: the host's peak resident size (wait4) of the long run, the broad
phase's own peak (stages.*.peak_memory_bytes), and on a GPU the largest device
memory in use during one more long run, apart from the timed ones (nvidia-smi
sampled every 20 ms, less what was in use before it started: its queries slow
the scan they watch).

Scenes (those whose files are missing are skipped, with a note):
  cloth_ball      cloth_ball92 -> 93 of the shared meshes (92,230 triangles)
  cloth_ball_obj  the same two frames written as an OBJ sequence (six decimals, as
                  Blender writes them) into --work: what reading text costs
  sample          samples/cloth_ball (its manifest: cloth and ball, rules), from frame 20
  cloth_ball_x4   cloth_ball Loop-subdivided once (368,920 triangles), the whole step
  cloth_ball_x16  twice (1,475,680 triangles), the whole step; written by
                  snag-bench-gpu --write-refined (needs CUDA) into --work
  sheet_floor     bench/report/make_long_cache.py: a 100 x 100 sheet falling on a floor
  cloth_funnel    a 96 x 96 cloth (18,432 triangles, self-collision on) jammed in the
                  neck of a funnel, baked by Blender's cloth solver
                  (scripts/bake_cloth_cache.py --body funnel) from frame 33 on,
                  where it lies bunched layer on layer: a long cache of tight
                  contact. Read from --work/cloth_funnel, baked there first when
                  `blender` is on the PATH (about a minute on 2 cores; the bake
                  script needs numpy in Blender's Python: Debian's python3-numpy)

--grids runs every scene with each grid named (snag-scan --grid: uniform, the
adaptive grid whose crowded cells are split), side by side in one call.

--check-cpu also scans each scene's short selection with --backend cpu and
compares every event line of the reports (--max-events 0): the GPU must
report the same events, bit for bit, with every grid of --grids.

Times are of one machine and one call: compare figures of the same call;
each figure is the median of --runs runs. Hosts differ, and one host drifts
from minute to minute (the same build on three H100 hosts: cloth_ball_x4
with static detection 9.8, 12.3 and 16.6 ms a step, most of the difference
in the host's stages: reading, the report): the first line names the
machine (processor, logical cores, GPU). To compare two builds, give the
other one as --baseline. Their runs then alternate (one of each in turn,
every scene, mode and grid), both get a row, and a line gives the new
median over the baseline's and in how many runs, paired in turn, the new
one was faster.

    scan_bench.py [--build DIR | --scan EXE [--bench-gpu EXE]] [--baseline EXE] [--backend cuda|cpu]
                  [--scenes a,b,...] [--frames N] [--runs N] [--modes ccd,all] [--grids uniform,adaptive]
                  [--check-cpu] [--work DIR] [--json FILE]
"""
import argparse
import hashlib
import json
import os
import shutil
import struct
import statistics
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "bench", "report"))
from report_bench import trailer  # noqa: E402  (the report's last record)
BACKEND_STAGES = ["ccd_broad", "ccd_narrow", "certification", "static_broad", "static_narrow"]
STAGES = ["read"] + BACKEND_STAGES + ["report_wait"]
FUNNEL_FROM = 33  # cloth_funnel's first frame: by then the cloth is jammed in the neck


def machine():
    """The host's processor and logical cores, and the GPUs nvidia-smi lists (None without it)."""
    processor = "unknown processor"
    try:
        with open("/proc/cpuinfo") as info:
            processor = next((line.split(":", 1)[1].strip() for line in info if line.startswith("model name")),
                             processor)
    except OSError:
        pass
    gpus = None
    if shutil.which("nvidia-smi") is not None:
        out = subprocess.run(["nvidia-smi", "--query-gpu=name", "--format=csv,noheader"], capture_output=True,
                             text=True)
        gpus = [line.strip() for line in out.stdout.splitlines() if line.strip()] if out.returncode == 0 else None
    return {"processor": processor, "cores": os.cpu_count(), "gpus": gpus}


class DeviceMemorySampler:
    """Largest device memory in use (MiB) while it runs, from nvidia-smi."""

    def __init__(self):
        self.process = None
        self.values = []
        if shutil.which("nvidia-smi") is None:
            return
        self.baseline = self._used_now()
        self.process = subprocess.Popen(["nvidia-smi", "--query-gpu=memory.used", "--format=csv,noheader,nounits",
                                         "-lms", "20"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        self.reader = threading.Thread(target=self._read)
        self.reader.start()

    @staticmethod
    def _used_now():
        out = subprocess.run(["nvidia-smi", "--query-gpu=memory.used", "--format=csv,noheader,nounits"],
                             capture_output=True, text=True).stdout.split()
        return float(out[0]) if out else 0.0

    def _read(self):
        for line in self.process.stdout:
            try:
                self.values.append(float(line.split()[0]))
            except (ValueError, IndexError):
                pass

    def stop(self):
        """Returns the peak above the baseline in MiB, or None without nvidia-smi."""
        if self.process is None:
            return None
        self.process.terminate()
        self.process.wait()
        self.reader.join()
        return max(0.0, max(self.values, default=self.baseline) - self.baseline)


def run_scan(command, sample_device=False):
    """Runs snag-scan; returns (peak host RSS MiB, peak device MiB or None, wall seconds)."""
    sampler = DeviceMemorySampler() if sample_device else None
    with tempfile.TemporaryFile(mode="w+") as err:
        start = time.perf_counter()
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(process.pid, 0)
        wall = time.perf_counter() - start
        code = os.waitstatus_to_exitcode(status)
        device = sampler.stop() if sampler else None
        if code not in (0, 1):  # 1: the scan found what fails it, which is not an error here
            err.seek(0)
            sys.exit(f"scan_bench: {' '.join(command)} failed ({code}): {err.read().strip()}")
    return usage.ru_maxrss / 1024, device, wall


def stage_seconds(t):
    """The trailer's stage times, flattened to STAGES, plus total."""
    timing = t["timing"]
    return {"read": timing["read"], "ccd_broad": timing["ccd_broad_phase"]["total"],
            "ccd_narrow": timing["ccd_narrow_phase"], "certification": timing["certification"],
            "static_broad": timing["static_broad_phase"]["total"], "static_narrow": timing["static_narrow_phase"],
            "report_wait": timing["report_wait"], "report": timing["report"], "total": timing["total"]}


def broad_peak_mib(t):
    stages = t.get("stages", {})
    return max(stages.get(k, {}).get("peak_memory_bytes", 0) for k in ("ccd_broad_phase", "static_broad_phase")) / 2**20


def event_digest(path):
    """(event lines, SHA-256 of them in report order): the events a report lists."""
    digest = hashlib.sha256()
    count = 0
    with open(path, "rb") as report:
        for line in report:
            if line.startswith(b'{"record":"event"'):
                digest.update(line)
                count += 1
    return count, digest.hexdigest()


class Scene:
    def __init__(self, name, triangles, inputs, frame_count=None):
        """inputs(frames) -> snag-scan arguments selecting `frames` frames; frame_count: the cache's, if fixed."""
        self.name, self.triangles, self.inputs, self.frame_count = name, triangles, inputs, frame_count


def alternating(t0, t1):
    return lambda frames: ["--sequence", *[(t0, t1)[k % 2] for k in range(frames)]]


def ply_to_obj(ply, obj):
    """Writes a binary PLY mesh (float x, y, z first among the vertex's
    properties, faces as uchar-counted int lists) as OBJ with six decimals."""
    with open(ply, "rb") as f:
        data = f.read()
    body = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:body].decode("ascii").split("\n")
    order = ">" if "format binary_big_endian 1.0" in header else "<"
    counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element ")}
    vertex_props = []
    for line in header:
        if line.startswith("element "):
            element = line.split()[1]
        elif line.startswith("property ") and element == "vertex":
            vertex_props.append(line.split()[1])
    assert vertex_props[:3] == ["float"] * 3 and set(vertex_props) == {"float"}, f"{ply}: unexpected vertex layout"
    stride = 4 * len(vertex_props)
    lines = []
    for k in range(counts["vertex"]):
        x, y, z = struct.unpack_from(order + "3f", data, body + k * stride)
        lines.append(f"v {x:.6f} {y:.6f} {z:.6f}\n")
    at = body + counts["vertex"] * stride
    for _ in range(counts["face"]):
        n = data[at]
        ids = struct.unpack_from(order + f"{n}i", data, at + 1)
        lines.append("f " + " ".join(str(i + 1) for i in ids) + "\n")
        at += 1 + 4 * n
    with open(obj, "w") as f:
        f.write("# cloth_ball, from " + os.path.basename(ply) + "\no cloth_ball\n")
        f.writelines(lines)


def make_scenes(args, work):
    scenes = {}
    meshes = args.meshes
    m92, m93 = os.path.join(meshes, "cloth_ball92.ply"), os.path.join(meshes, "cloth_ball93.ply")
    if os.path.exists(m92) and os.path.exists(m93):
        scenes["cloth_ball"] = Scene("cloth_ball", 92230, alternating(m92, m93))
        if "cloth_ball_obj" in args.scenes.split(","):
            objs = [os.path.join(work, "cloth_ball_obj", f"cloth_ball{k}.obj") for k in (92, 93)]
            if not all(os.path.exists(obj) for obj in objs):
                os.makedirs(os.path.dirname(objs[0]), exist_ok=True)
                for ply, obj in zip((m92, m93), objs):
                    ply_to_obj(ply, obj)
            scenes["cloth_ball_obj"] = Scene("cloth_ball_obj", 92230, alternating(*objs))
    manifest = os.path.join(args.samples, "cloth_ball", "scene.yaml")
    if os.path.exists(manifest):
        # From frame 20 on, where the cloth lies on the ball (the first frames have no contact).
        scenes["sample"] = Scene("sample", None,
                                 lambda frames: ["--manifest", manifest, "--frames", f"20:{20 + frames - 1}"], 20)
    wanted = args.scenes.split(",")
    if any(s.startswith("cloth_ball_x") for s in wanted) and args.bench_gpu and os.access(args.bench_gpu, os.X_OK):
        refined = os.path.join(work, "refined")
        if not os.path.exists(os.path.join(refined, "cloth_ball_x16_t1.ply")):
            subprocess.run([args.bench_gpu, "--write-refined", refined], check=True, stdout=subprocess.DEVNULL)
        for factor, triangles in ((4, 368920), (16, 1475680)):
            stem = os.path.join(refined, f"cloth_ball_x{factor}")
            scenes[f"cloth_ball_x{factor}"] = Scene(f"cloth_ball_x{factor}", triangles,
                                                    alternating(stem + "_t0.ply", stem + "_t1.ply"))
    if "sheet_floor" in wanted:
        long_dir = os.path.join(work, "sheet_floor")
        if not os.path.exists(os.path.join(long_dir, "floor.obj")):
            subprocess.run([sys.executable, os.path.join(ROOT, "bench", "report", "make_long_cache.py"), long_dir,
                            str(max(args.frames, 12))], check=True, stdout=subprocess.DEVNULL)
        sheet_files = [os.path.join(long_dir, "sheet.pc2"), "-t", os.path.join(long_dir, "sheet.obj"),
                       os.path.join(long_dir, "floor.pc2"), "-t", os.path.join(long_dir, "floor.obj")]
        scenes["sheet_floor"] = Scene("sheet_floor", None,
                                      lambda frames: [*sheet_files, "--frames", f"0:{frames - 1}"])
    if "cloth_funnel" in wanted:
        funnel = os.path.join(work, "cloth_funnel")
        names = [os.path.join(funnel, name) for name in ("cloth.pc2", "cloth_rest.obj", "body.pc2", "body_rest.obj")]
        if not all(os.path.exists(name) for name in names) and shutil.which("blender"):
            subprocess.run(["blender", "-b", "--factory-startup", "--python",
                            os.path.join(ROOT, "scripts", "bake_cloth_cache.py"), "--", funnel, "--cells", "96",
                            "--frames", str(FUNNEL_FROM - 1 + max(args.frames, 12)), "--body", "funnel",
                            "--self-collision", "--keep-from", str(FUNNEL_FROM)], check=True, stdout=subprocess.DEVNULL)
        if all(os.path.exists(name) for name in names):
            funnel_files = [names[0], "-t", names[1], names[2], "-t", names[3]]
            with open(names[0], "rb") as pc2:  # a bake of another run may hold fewer frames than asked for
                frame_count = struct.unpack("<i", pc2.read(32)[28:32])[0]
            scenes["cloth_funnel"] = Scene("cloth_funnel", 18528,
                                           lambda frames: [*funnel_files, "--frames", f"0:{frames - 1}"],
                                           frame_count)
    return scenes


def scan_command(args, scan, scene, frames, mode, grid, work):
    """snag-scan over `frames` frames of the scene, and the path of the report it writes."""
    path = os.path.join(work, f"{scene.name}_{mode}_{grid}_{frames}.jsonl")
    return [scan, *scene.inputs(frames), "-b", args.backend, "-m", mode, "--grid", grid, "-q", "-r", path], path


def one_run(args, scan, scene, mode, grid, work):
    """One run of `scan` on a scene: its short and long selections (their trailers' times) and memory."""
    long_frames = args.frames if scene.frame_count is None else min(args.frames, scene.frame_count)
    run = {"totals": {}}
    if long_frames <= args.short_frames:
        sys.exit(f"scan_bench: {scene.name} has {long_frames} frames, not more than --short-frames")
    run["short"] = args.short_frames
    for frames in (args.short_frames, long_frames):
        command, path = scan_command(args, scan, scene, frames, mode, grid, work)
        rss, _, wall = run_scan(command)
        t = trailer(path)
        run["totals"][frames] = stage_seconds(t)
        if frames == long_frames:
            run.update({"frames": long_frames, "rss": rss, "wall": wall,
                        "outside": wall - run["totals"][frames]["total"], "start": t["timing"].get("start", 0.0),
                        "broad_peak": broad_peak_mib(t), "stages": t.get("stages", {}),
                        "events": t["summary"]["events"]})
    return run


def summarize(scene, mode, grid, runs):
    """Medians over the runs of the per-step times (ms) of one scene, mode and grid, and memory."""
    long_frames, short = runs[0]["frames"], runs[0]["short"]
    per_step = {k: [1e3 * (r["totals"][long_frames][k] - r["totals"][short][k]) / (long_frames - short) for r in runs]
                for k in STAGES + ["report", "total"]}
    row = {k: statistics.median(v) for k, v in per_step.items()}
    row["backend"] = sum(row[k] for k in BACKEND_STAGES)
    # Reading runs on its own thread beside the rest: not part of the sum.
    row["other"] = row["total"] - sum(row[k] for k in STAGES if k != "read")
    row.update({"scene": scene.name, "mode": mode, "grid": grid, "triangles": scene.triangles, "frames": long_frames,
                "runs": len(runs), "events_long": runs[-1]["events"], "host_peak_mib": max(r["rss"] for r in runs),
                "broad_peak_mib": max(r["broad_peak"] for r in runs),
                "total_spread_ms": [min(per_step["total"]), max(per_step["total"])],
                "total_per_run_ms": per_step["total"], "stages": runs[-1]["stages"],
                "wall_s": statistics.median(r["wall"] for r in runs),
                "outside_ms": 1e3 * statistics.median(r["outside"] for r in runs),
                "start_ms": 1e3 * statistics.median(r["start"] for r in runs),
                "short_frames": short, "short_ms": 1e3 * statistics.median(r["totals"][short]["total"] for r in runs),
                "long_total_ms": 1e3 * statistics.median(r["totals"][long_frames]["total"] for r in runs)})
    return row


def measure(args, scene, mode, grid, work):
    """{variant: row}: args.scan's medians, and with --baseline the baseline's, their runs taken in turn (a
    run of one, then of the other), so that both meet the same drift of the machine."""
    scans = {"scan": args.scan} if args.baseline is None else {"baseline": args.baseline, "scan": args.scan}
    runs = {variant: [] for variant in scans}
    for _ in range(args.runs):
        for variant, scan in scans.items():
            runs[variant].append(one_run(args, scan, scene, mode, grid, work))
    rows = {variant: summarize(scene, mode, grid, r) for variant, r in runs.items()}
    for variant, scan in scans.items():
        frames = runs[variant][0]["frames"]
        rows[variant]["device_peak_mib"] = device_peak_mib(args, scan, scene, mode, grid, work, frames)
    return rows


def device_peak_mib(args, scan, scene, mode, grid, work, frames):
    """The largest device memory in use during one more long run (MiB above what was in use before it), or
    None on the CPU back end or without nvidia-smi. Apart from the timed runs: nvidia-smi's queries every
    20 ms slow the scan they watch (by 0.1 to 0.2 ms a step of cloth_ball, CCD and static, on an H200)."""
    if args.backend != "cuda":
        return None
    _, device, _ = run_scan(scan_command(args, scan, scene, frames, mode, grid, work)[0], sample_device=True)
    return device


def compare(base, new):
    """The new scan's median total per step over the baseline's, and in how many of the runs (paired in the
    order they ran) the new one took less."""
    pairs = list(zip(base["total_per_run_ms"], new["total_per_run_ms"]))
    return {"scene": base["scene"], "mode": base["mode"], "grid": base["grid"], "baseline_ms": base["total"],
            "new_ms": new["total"], "ratio": new["total"] / base["total"] if base["total"] > 0 else float("nan"),
            "faster_runs": sum(1 for b, n in pairs if n < b), "runs": len(pairs)}


def check_cpu(args, scene, grids, work):
    """Same events from the CPU back end (uniform grid) and from args.backend with
    each grid, on the scene's first step (and its two frames)."""
    runs = [("cpu", "uniform")] + [(args.backend, grid) for grid in grids]
    digests = {}
    for backend, grid in runs:
        path = os.path.join(work, f"{scene.name}_check_{backend}_{grid}.jsonl")
        run_scan([args.scan, *scene.inputs(2), "-b", backend, "-m", "all", "--grid", grid, "--max-events", "0", "-q",
                  "-r", path])
        digests[f"{backend} {grid}"] = event_digest(path)
    same = all(d == digests["cpu uniform"] for d in digests.values())
    return {"scene": scene.name, "events": digests["cpu uniform"][0], "same": same,
            **{k: d[1][:16] for k, d in digests.items()}}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--scan")
    parser.add_argument("--bench-gpu")
    parser.add_argument("--backend", default="cuda", choices=["cpu", "cuda"])
    parser.add_argument("--scenes", default="cloth_ball,sample,cloth_ball_x4,cloth_ball_x16,sheet_floor")
    parser.add_argument("--modes", default="ccd,all")
    parser.add_argument("--grids", default="uniform", help="snag-scan --grid values, comma-separated")
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--short-frames", type=int, default=2, help="the short selection's frames (at least 2)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--check-cpu", action="store_true")
    parser.add_argument("--meshes", default=os.path.join(ROOT, "..", "shared", "data", "meshes"))
    parser.add_argument("--samples", default=os.path.join(ROOT, "samples"))
    parser.add_argument("--work")
    parser.add_argument("--json", help="also write the numbers here")
    parser.add_argument("--baseline", help="another snag-scan to compare with: its runs alternate with --scan's")
    args = parser.parse_args()
    if args.short_frames < 2 or args.frames <= args.short_frames or args.runs < 1:
        parser.error("--short-frames must be at least 2, --frames more than it and --runs at least 1")
    args.scan = args.scan or os.path.join(args.build, "tools", "snag-scan")
    args.bench_gpu = args.bench_gpu or os.path.join(args.build, "bench", "gpu", "snag-bench-gpu")
    if not os.access(args.scan, os.X_OK):
        parser.error(f"{args.scan}: no snag-scan there (give --build or --scan)")
    if args.baseline is not None and not os.access(args.baseline, os.X_OK):
        parser.error(f"{args.baseline}: no snag-scan there")
    work = args.work or tempfile.mkdtemp(prefix="snag-scan-bench-")
    os.makedirs(work, exist_ok=True)
    scenes = make_scenes(args, work)
    host = machine()
    results = {"backend": args.backend, "frames": args.frames, "runs": args.runs, "machine": host, "rows": [],
               "comparisons": [], "checks": []}
    print(f"== machine: {host['processor']}, {host['cores']} logical cores; "
          f"GPU: {', '.join(host['gpus']) if host['gpus'] else 'none listed'}")

    print(f"== per step through snag-scan --backend {args.backend}, ms (median of {args.runs}; "
          f"(total of {args.frames} frames - total of {args.short_frames}) / {args.frames - args.short_frames})")
    grids = args.grids.split(",")
    if any(g not in ("uniform", "adaptive") for g in grids):
        parser.error("--grids takes uniform and adaptive")
    width = 15 if args.baseline is None else 22  # the scene's name, and with --baseline which build ran
    header = (f"{'scene':<{width}} {'mode':<4} {'grid':<8} {'total':>8} {'backend':>8} {'read':>6} {'ccd bp':>7} {'ccd np':>7} "
              f"{'certif':>7} {'st bp':>7} {'st np':>7} {'report':>7} {'rep wait':>8} {'other':>7} {'dev MiB':>8} {'bp MiB':>7} "
              f"{'host MiB':>8} {'wall s':>7} {'outside':>7} {'start':>6} {f'{args.short_frames}-fr ms':>8}")
    print(header)
    for name in args.scenes.split(","):
        if name not in scenes:
            print(f"{name:<{width}} (skipped: its files or snag-bench-gpu are missing)")
            continue
        for mode in args.modes.split(","):
            for grid in grids:
                rows = measure(args, scenes[name], mode, grid, work)
                for variant, row in rows.items():
                    row["variant"] = variant
                    results["rows"].append(row)
                    device = "-" if row["device_peak_mib"] is None else f"{row['device_peak_mib']:.0f}"
                    label = name if args.baseline is None else f"{name} ({'base' if variant == 'baseline' else 'new'})"
                    print(f"{label:<{width}} {mode:<4} {grid:<8} {row['total']:>8.2f} {row['backend']:>8.2f} {row['read']:>6.2f} "
                          f"{row['ccd_broad']:>7.2f} {row['ccd_narrow']:>7.2f} {row['certification']:>7.2f} "
                          f"{row['static_broad']:>7.2f} {row['static_narrow']:>7.2f} {row['report']:>7.2f} "
                          f"{row['report_wait']:>8.2f} {row['other']:>7.2f} {device:>8} {row['broad_peak_mib']:>7.0f} "
                          f"{row['host_peak_mib']:>8.0f} {row['wall_s']:>7.2f} {row['outside_ms']:>7.0f} "
                          f"{row['start_ms']:>6.0f} {row['short_ms']:>8.1f}",
                          flush=True)
                if args.baseline is not None:
                    comparison = compare(rows["baseline"], rows["scan"])
                    results["comparisons"].append(comparison)
                    print(f"{'':<{width}} {mode:<4} {grid:<8} new/base {comparison['ratio']:.3f}; new faster in "
                          f"{comparison['faster_runs']} of {comparison['runs']} runs", flush=True)
    if args.check_cpu and args.backend != "cpu":
        print(f"== same events as the CPU back end (first step, every event listed)")
        for name in args.scenes.split(","):
            if name in scenes and name != "cloth_ball_x16":  # the CPU back end takes minutes on it
                check = check_cpu(args, scenes[name], grids, work)
                results["checks"].append(check)
                print(f"{name:<{width}} {check['events']:>9} events  {'same' if check['same'] else 'DIFFERENT'}", flush=True)
    if args.json:
        with open(args.json, "w") as out:
            json.dump(results, out, indent=1)
    print(f"scan_bench: files in {work}")
    if any(not c["same"] for c in results["checks"]):
        sys.exit(1)


if __name__ == "__main__":
    main()
