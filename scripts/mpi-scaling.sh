#!/usr/bin/env bash
# Measures snag-scan over MPI on the GPUs of one host, from a bundle made by
# scripts/make-mpi-bundle.sh: writes a long cache of a large cloth
# (mpi-make-cloth.py: FRAMES frames of an N x N sheet over a floor), scans it
# with one process without MPI, then under mpirun at each rank count, and
# prints wall time, speed-up and parallel efficiency against the one process,
# and whether each report is the one process's (all but the process measures:
# the trailer's timing and the stages' peak_memory_bytes).
#
# With bin/snag-scan-old in the bundle (make-mpi-bundle.sh's SNAG_OLD_SCAN),
# each rank count runs that build too, rows marked "old", against the same
# one process. NEW_MERGE_COST: SNAG_MPI_MERGE_COST for the new build's ranks only.
#
# Usage:  mpi-scaling.sh WORKDIR FRAMES N RANKS... [-- snag-scan options]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$1 frames=$2 n=$3
shift 3
ranks=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do ranks+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
calc() { python3 -c "print(round($1, 3))"; }
mkdir -p "$work"
cache=$work/cache
start=$(date +%s.%N)
python3 "$here/mpi-make-cloth.py" "$cache" "$frames" "$n" || exit 1
echo "cache: $frames frames, sheet $n x $n ($((n * n)) vertices, $((2 * (n - 1) * (n - 1))) triangles) + floor;" \
  "written in $(calc "$(date +%s.%N) - $start") s"
inputs=("$cache/sheet.pc2" -t "$cache/sheet.obj" "$cache/floor.pc2" -t "$cache/floor.obj" -q "$@")

seconds() {  # runs the command, prints its wall time; its exit status 0 or 1 is a finished scan
  local t0 t1 status
  t0=$(date +%s.%N)
  "$@" >"$work/last.out" 2>&1
  status=$?
  t1=$(date +%s.%N)
  if [ "$status" -gt 1 ]; then
    echo "failed ($status): $*" >&2
    cat "$work/last.out" >&2
    return 1
  fi
  calc "$t1 - $t0"
}
same_report() {
  python3 - "$1" "$2" <<'PY'
import re, sys
def measured_out(path):
    text = open(path).read()
    trailer = text.rindex('{"record":"trailer"')
    timing = text.index(',"timing":', trailer)
    return text[:trailer] + re.sub(r'"peak_memory_bytes":[0-9]+', '"peak_memory_bytes":N', text[trailer:timing])
a, b = measured_out(sys.argv[1]), measured_out(sys.argv[2])
if a == b:
    print("yes")
else:  # where they part, for the log
    lines = [(n, x, y) for n, (x, y) in enumerate(zip(a.split("\n"), b.split("\n")), 1) if x != y]
    n, x, y = lines[0] if lines else (0, "", "")
    print(f"NO (line {n}: {x[:300]} | {y[:300]})", file=sys.stderr)
    print("NO")
PY
}

# snag-scan alone loads Open MPI's libraries from the bundle too.
libraries=$here/ompi/lib/x86_64-linux-gnu/openmpi/lib:$here/pmix2/lib:$here/lib
one=$(seconds env LD_LIBRARY_PATH="$libraries" "$here/bin/snag-scan" "${inputs[@]}" -r "$work/one.jsonl") || exit 1
python3 -c "import json; t=json.loads(open('$work/one.jsonl').readlines()[-1]); s=t['summary'];
h=json.loads(open('$work/one.jsonl').readline())
print('one process (%s): %s s; %d events, %d regions, %d tracks; report %.2f s of it (%.3f of the scan: a merge cost)' % (h['settings']['backend'], '$one', s['events'], s['regions'], s['tracks'], t['timing']['report'], t['timing']['report'] / t['timing']['total']))"
# after last: rank 0's seconds once the other ranks were done (the trailer's
# timing.after_last_rank); merge cost: rank 0's join time per frame of the
# other ranks' parts (timing.join) over the one process's time per frame.
builds=(new)
[ -x "$here/bin/snag-scan-old" ] && builds+=(old)
printf '%-10s %10s %9s %11s %10s %11s %11s\n' ranks seconds speed-up efficiency identical 'after last' 'merge cost'
for k in "${ranks[@]}"; do
  for build in "${builds[@]}"; do
    exe=$here/bin/snag-scan label=$k cost_setting=()
    [ -n "${NEW_MERGE_COST:-}" ] && cost_setting=(SNAG_MPI_MERGE_COST="$NEW_MERGE_COST")
    [ "$build" = old ] && exe=$here/bin/snag-scan-old label="$k old" cost_setting=()
    report=$work/$k-$build.jsonl
    t=$(seconds env "${cost_setting[@]}" "$here/mpi-run.sh" -n "$k" --bind-to none "$exe" "${inputs[@]}" -r "$report") || exit 1
    read -r after cost < <(python3 -c "import json; t=json.loads(open('$report').readlines()[-1])['timing']
frames = t.get('joined_frames', 0)
cost = t['join'] / frames / ($one / $frames) if frames else float('nan')
print(round(t.get('after_last_rank', 0), 3), round(cost, 4) if frames else '-')")
    printf '%-10s %10.2f %9.2f %11.2f %10s %11s %11s\n' "$label" "$t" "$(calc "$one / $t")" "$(calc "$one / $t / $k")" \
      "$(same_report "$work/one.jsonl" "$report")" "$after" "$cost"
  done
done
