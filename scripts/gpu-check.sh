#!/usr/bin/env bash
# Runs snag's GPU checks on a machine with an NVIDIA GPU, from the bundle made
# by scripts/make-gpu-bundle.sh only: it builds nothing and needs no toolkit.
#
# Usage:  bash scripts/gpu-check.sh [LOG_DIR]        (from the project root), or
#         bash .gpu-bundle/gpu-check.sh [LOG_DIR]    (the copy inside the bundle)
#   LOG_DIR        where logs and JSON results go (default ./gpu-logs)
#   SNAG_BUNDLE    the bundle folder, when it is not next to this script
#                  (default: this script's folder if it holds manifest.txt,
#                  else ../.gpu-bundle from it)
#   SANITIZER_TIMEOUT  seconds per compute-sanitizer run (default 600)
#   SNAG_SANITIZERS    the compute-sanitizer tools to run (default "memcheck racecheck")
#   SNAG_GPU_CHECK_BENCH  0: leave out the benchmarks (default 1)
#
# Steps: nvidia-smi; every GPU test executable with --gtest_output=json; each
# under compute-sanitizer memcheck (with leak check) and racecheck when
# compute-sanitizer is found (PATH, /usr/local/cuda); every GPU benchmark
# (Google Benchmark, JSON out); snag-scan --version when present; with the
# device tracer, a timeline of snag-scan on a 22-frame cloth_ball sequence in
# each mode, summed up per step (trace-MODE.txt; the CUPTI library is taken
# from the machine's CUDA toolkit, /usr/local/cuda). A summary
# table comes last. Exit status: 0 when every step that ran passed, else 1;
# GPU tests that skip count as failed when nvidia-smi lists a GPU.
set -uo pipefail

here=$(cd "$(dirname "$0")" && pwd)
if [ -n "${SNAG_BUNDLE:-}" ]; then
  bundle=$SNAG_BUNDLE
elif [ -f "$here/manifest.txt" ]; then
  bundle=$here
else
  bundle=$here/../.gpu-bundle
fi
[ -f "$bundle/manifest.txt" ] || { echo "gpu-check: no bundle at $bundle (run scripts/make-gpu-bundle.sh where snag builds)" >&2; exit 2; }
bundle=$(cd "$bundle" && pwd)
logs=${1:-./gpu-logs}
mkdir -p "$logs"
logs=$(cd "$logs" && pwd)
sanitizer_timeout=${SANITIZER_TIMEOUT:-600}
sanitizer_skip=${SNAG_SANITIZER_SKIP:-*ClothBall*}

export LD_LIBRARY_PATH="$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export SNAG_SHARED_DATA_DIR="$bundle/data"
# The sample caches: the project's samples/ beside the bundle, unless given.
if [ -z "${SNAG_SAMPLES_DIR:-}" ] && [ -d "$bundle/../samples/cloth_ball" ]; then
  export SNAG_SAMPLES_DIR="$(cd "$bundle/../samples" && pwd)"
fi

summary=()
failed=0
# record STEP RESULT DETAIL SECONDS
record() {
  summary+=("$(printf '%-44s %-6s %6ss  %s' "$1" "$2" "$4" "$3")")
  [ "$2" = "FAIL" ] && failed=1
  return 0
}

echo "== bundle"
cat "$bundle/BUILD_INFO"
echo "== system"
(. /etc/os-release 2>/dev/null && echo "$PRETTY_NAME"); uname -r
ldd --version 2>/dev/null | head -1

# Our libstdc++ / libgcc_s only when the system's are too old for our executables.
first_binary=$(awk 'NR == 1 {print $3}' "$bundle/manifest.txt")
if ldd "$bundle/$first_binary" 2>&1 | grep -q 'not found'; then
  export LD_LIBRARY_PATH="$bundle/lib/compat:$LD_LIBRARY_PATH"
  echo "using the bundle's libstdc++/libgcc_s (the system's are older)"
fi
if ldd "$bundle/$first_binary" 2>&1 | grep 'not found'; then
  echo "gpu-check: libraries missing (above); this system is older than the build's (see glibc_need)" >&2
fi

echo "== nvidia-smi"
gpu_listed=0
if command -v nvidia-smi >/dev/null && nvidia-smi -L 2>/dev/null | grep -q '^GPU '; then
  gpu_listed=1
fi
if command -v nvidia-smi >/dev/null; then
  nvidia-smi 2>&1 | tee "$logs/nvidia-smi.txt"
  nvidia-smi --query-gpu=name,driver_version,memory.total,compute_cap --format=csv 2>&1 | tee -a "$logs/nvidia-smi.txt"
else
  echo "nvidia-smi not found" | tee "$logs/nvidia-smi.txt"
fi

sanitizer=""
for candidate in "$(command -v compute-sanitizer 2>/dev/null)" /usr/local/cuda/bin/compute-sanitizer \
  /usr/local/cuda/compute-sanitizer/compute-sanitizer; do
  if [ -n "$candidate" ] && [ -x "$candidate" ]; then
    sanitizer=$candidate
    break
  fi
done

# gtest_counts LOG: "P passed, S skipped, F failed" from a GoogleTest log.
gtest_counts() {
  local passed skipped failed_count
  passed=$(grep -oE '^\[  PASSED  \] [0-9]+' "$1" | grep -oE '[0-9]+$' || true)
  skipped=$(grep -oE '^\[  SKIPPED \] [0-9]+ test' "$1" | grep -oE '[0-9]+' || true)
  failed_count=$(grep -oE '^\[  FAILED  \] [0-9]+ test' "$1" | grep -oE '[0-9]+' || true)
  echo "${passed:-0} passed, ${skipped:-0} skipped, ${failed_count:-0} failed"
}

while read -r kind name path; do
  binary=$bundle/$path
  case "$kind" in
    test)
      echo "== test $name"
      start=$SECONDS
      "$binary" --gtest_output="json:$logs/$name.json" 2>&1 | tee "$logs/$name.log"
      rc=${PIPESTATUS[0]}
      counts=$(gtest_counts "$logs/$name.log")
      # Skipped tests mean no usable GPU (the log says why): a failure when
      # nvidia-smi lists one, since then the GPU should have run them.
      result=PASS
      case "$counts" in *" 0 skipped"*) ;; *) result=SKIP; [ "$gpu_listed" = 1 ] && result=FAIL ;; esac
      [ "$rc" -ne 0 ] && result=FAIL
      record "test $name" "$result" "$counts" $((SECONDS - start))
      for tool in ${SNAG_SANITIZERS:-memcheck racecheck}; do
        if [ -z "$sanitizer" ]; then
          record "$tool $name" SKIP "compute-sanitizer not found" 0
          continue
        fi
        echo "== $tool $name"
        extra=()
        [ "$tool" = memcheck ] && extra=(--leak-check full)
        start=$SECONDS
        # CudaCheck.* makes failing CUDA calls on purpose (to test the error
        # reports); the sanitizer would count those as errors. The largest
        # scenes (SNAG_SANITIZER_SKIP, a gtest pattern) run tens of times
        # slower under the sanitizers; the smaller scenes exercise the same kernels.
        timeout "$sanitizer_timeout" "$sanitizer" --tool "$tool" "${extra[@]}" --error-exitcode 99 \
          "$binary" --gtest_brief=1 --gtest_filter="-CudaCheck.*:$sanitizer_skip" >"$logs/$name.$tool.log" 2>&1
        rc=$?
        tail -5 "$logs/$name.$tool.log"
        summary_line=$(grep -E 'ERROR SUMMARY|RACECHECK SUMMARY|LEAK SUMMARY' "$logs/$name.$tool.log" | tail -1)
        case "$rc" in
          0) record "$tool $name" PASS "${summary_line:-no errors}" $((SECONDS - start)) ;;
          124) record "$tool $name" FAIL "timed out after ${sanitizer_timeout}s" $((SECONDS - start)) ;;
          *) record "$tool $name" FAIL "exit $rc; ${summary_line:-see $name.$tool.log}" $((SECONDS - start)) ;;
        esac
      done
      ;;
    bench)
      if [ "${SNAG_GPU_CHECK_BENCH:-1}" = 0 ]; then
        record "bench $name" SKIP "SNAG_GPU_CHECK_BENCH=0" 0
        continue
      fi
      echo "== bench $name"
      start=$SECONDS
      "$binary" --benchmark_out="$logs/$name.json" --benchmark_out_format=json 2>&1 | tee "$logs/$name.log"
      rc=${PIPESTATUS[0]}
      if [ "$rc" -eq 0 ]; then
        record "bench $name" PASS "results in $name.json" $((SECONDS - start))
      else
        record "bench $name" FAIL "exit $rc" $((SECONDS - start))
      fi
      ;;
    trace)
      cupti=$(ls -d /usr/local/cuda/lib64/libcupti.so* /usr/local/cuda/extras/CUPTI/lib64/libcupti.so* \
        /usr/local/cuda-*/lib64/libcupti.so* 2>/dev/null | head -1)
      meshes=$bundle/data/meshes
      if [ "${SNAG_GPU_CHECK_BENCH:-1}" = 0 ] || [ -z "$cupti" ] || [ ! -x "$bundle/bin/snag-scan" ]; then
        record "trace $name" SKIP "benchmarks off, no CUPTI in /usr/local/cuda, or no snag-scan" 0
        continue
      fi
      sequence=()
      for k in $(seq 0 21); do sequence+=("$meshes/cloth_ball9$((2 + k % 2)).ply"); done
      for mode in ccd all; do
        echo "== trace $name: snag-scan -m $mode, cloth_ball 22 frames"
        start=$SECONDS
        LD_LIBRARY_PATH="$(dirname "$cupti"):$LD_LIBRARY_PATH" CUDA_INJECTION64_PATH="$binary" \
          SNAG_CUPTI_TRACE="$logs/trace-$mode.csv" "$bundle/bin/snag-scan" --sequence "${sequence[@]}" -b cuda \
          -m "$mode" -q -r "$logs/trace-$mode.jsonl" >"$logs/trace-$mode.log" 2>&1
        rc=$?  # 1: events found
        python3 "$bundle/trace_summary.py" --steps 21 "$logs/trace-$mode.csv" 2>&1 | tee "$logs/trace-$mode.txt"
        summary_rc=${PIPESTATUS[0]}
        if [ "$rc" -le 1 ] && [ "$summary_rc" -eq 0 ]; then
          record "trace $name -m $mode" PASS "$(sed -n 2p "$logs/trace-$mode.txt")" $((SECONDS - start))
        else
          record "trace $name -m $mode" FAIL "snag-scan exit $rc; see trace-$mode.log" $((SECONDS - start))
        fi
      done
      ;;
    tool)
      echo "== tool $name"
      start=$SECONDS
      "$binary" --version >"$logs/$name.log" 2>&1
      rc=$?
      cat "$logs/$name.log"
      if [ "$rc" -eq 0 ]; then
        record "tool $name --version" PASS "$(head -1 "$logs/$name.log")" $((SECONDS - start))
      else
        record "tool $name --version" FAIL "exit $rc" $((SECONDS - start))
      fi
      ;;
  esac
done < <(awk '$1 == "test"' "$bundle/manifest.txt"; awk '$1 == "tool"' "$bundle/manifest.txt";
          awk '$1 == "bench"' "$bundle/manifest.txt"; awk '$1 == "trace"' "$bundle/manifest.txt")  # tests first: they say whether the timings mean anything

echo
echo "== summary (logs in $logs)"
printf '%-44s %-6s %7s  %s\n' STEP RESULT TIME DETAIL
printf '%s\n' "${summary[@]}" | tee "$logs/summary.txt"
exit "$failed"
