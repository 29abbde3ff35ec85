#!/usr/bin/env bash
# The report's cost as a user meets it, through snag-scan, end to end:
#  1. memory on a long cache: a 500-frame synthetic cache (make_long_cache.py),
#     scanned at 50, 200 and 500 frames with every event listed; the peak
#     resident size of each run, and during the 500-frame run the resident
#     size sampled every 0.2 s (the largest in the first tenth of the run,
#     about its first 50 frames, against the largest after it);
#  2. the report's share of the time on the 12-frame cloth-ball sequence
#     (frames 92 and 93 of ../shared/data/meshes, repeated), CPU back end,
#     every event listed: the trailer's timing.report (rules, regions,
#     tracks, writing) against timing.total, and the peak resident size;
#  3. reading the reports back with the streaming reader (MB/s).
# Times are of this machine and this run; compare ratios, not seconds.
#
#   bench/report/report_bench.sh [BUILD_DIR] [WORK_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
work=${2:-$(mktemp -d)}
scan=$build/tools/snag-scan
read_bench=$build/bench/report/snag-bench-report-read
meshes=$root/../shared/data/meshes
mkdir -p "$work"
[ -x "$scan" ] || { echo "report_bench.sh: build snag-scan first ($scan)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "report_bench.sh: needs /usr/bin/time (Debian package time)" >&2; exit 2; }

peak_kb() { sed -n 's/.*Maximum resident set size (kbytes): //p' "$1"; }
trailer_timing() {  # FILE KEY: a number from the trailer's timing object
  tail -n 1 "$1" | python3 -c "import json,sys; print(json.load(sys.stdin)['timing']['$2'])"
}

echo "== 1. memory on a long cache (500 frames, sheet of 100 x 100 vertices over a floor) =="
python3 "$here/make_long_cache.py" "$work/long" 500
long=("$work/long/sheet.pc2" -t "$work/long/sheet.obj" "$work/long/floor.pc2" -t "$work/long/floor.obj")
printf '%8s %12s %10s %10s %12s\n' frames peak_MiB total_s report_s report_MB
for frames in 50 200 500; do
  /usr/bin/time -v "$scan" "${long[@]}" -b cpu --frames "0:$((frames - 1))" --max-events 0 -q \
    -r "$work/long_$frames.jsonl" 2>"$work/time_$frames.txt" || [ $? -eq 1 ]
  printf '%8d %12.1f %10.2f %10.3f %12.1f\n' "$frames" "$(echo "$(peak_kb "$work/time_$frames.txt") / 1024" | bc -l)" \
    "$(trailer_timing "$work/long_$frames.jsonl" total)" "$(trailer_timing "$work/long_$frames.jsonl" report)" \
    "$(echo "$(stat -c %s "$work/long_$frames.jsonl") / 1000000" | bc -l)"
done
echo "resident size during the 500-frame run:"
"$scan" "${long[@]}" -b cpu --max-events 0 -q -r "$work/long_sampled.jsonl" &
pid=$!
: > "$work/rss.txt"
start=$(date +%s.%N)
while kill -0 "$pid" 2>/dev/null; do
  rss=$(sed -n 's/^VmRSS:[[:space:]]*\([0-9]*\) kB/\1/p' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$rss" ] && echo "$(echo "$(date +%s.%N) - $start" | bc -l) $rss" >> "$work/rss.txt"
  sleep 0.2
done
wait "$pid" || [ $? -eq 1 ]
python3 - "$work/rss.txt" <<'PY'
import sys
samples = [tuple(map(float, line.split())) for line in open(sys.argv[1]) if line.strip()]
end = samples[-1][0]
early = max(kb for t, kb in samples if t <= 0.1 * end) / 1024
late = max(kb for t, kb in samples if t > 0.1 * end) / 1024
print(f"  {len(samples)} samples over {end:.1f} s; largest in the first tenth {early:.1f} MiB, after it {late:.1f} MiB "
      f"({100 * (late - early) / early:+.1f}%)")
PY

echo "== 2. the report's share of the time: cloth-ball 92/93 as a 12-frame sequence, CPU =="
sequence=()
for i in 1 2 3 4 5 6; do sequence+=("$meshes/cloth_ball92.ply" "$meshes/cloth_ball93.ply"); done
/usr/bin/time -v "$scan" --sequence "${sequence[@]}" -b cpu --max-events 0 -q -r "$work/cloth_ball_12.jsonl" \
  2>"$work/time_cloth_ball.txt" || [ $? -eq 1 ]
total=$(trailer_timing "$work/cloth_ball_12.jsonl" total)
report=$(trailer_timing "$work/cloth_ball_12.jsonl" report)
events=$(tail -n 1 "$work/cloth_ball_12.jsonl" | python3 -c "import json,sys; print(json.load(sys.stdin)['summary']['events'])")
printf '  %s events; scan %.2f s, of which the report %.3f s (%.1f%% of the scan); peak %.1f MiB; report %.1f MB\n' \
  "$events" "$total" "$report" "$(echo "100 * $report / ($total - $report)" | bc -l)" \
  "$(echo "$(peak_kb "$work/time_cloth_ball.txt") / 1024" | bc -l)" \
  "$(echo "$(stat -c %s "$work/cloth_ball_12.jsonl") / 1000000" | bc -l)"

echo "== 3. reading reports back (streaming reader, best of 3, file in the page cache) =="
if [ -x "$read_bench" ]; then
  "$read_bench" "$work/cloth_ball_12.jsonl" "$work/long_500.jsonl"
else
  echo "  (snag-bench-report-read not built)"
fi
echo "report_bench.sh: files in $work"
