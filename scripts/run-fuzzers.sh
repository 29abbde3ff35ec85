#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, address + undefined sanitizers) in
# build-fuzz/ and runs each for a fixed time from its seed corpus in
# fuzz/corpus/<format>/ (meshes, point caches, reports, scene manifests). New inputs go to build-fuzz/corpus/<format>/ so the
# committed seeds stay small. Then each target runs once over every file of
# fuzz/corpus-degenerate/<format>/ (degenerate meshes: collapsed triangles,
# coincident vertices, zero-length edges, huge and tiny coordinates, repeated
# indices; libFuzzer's -runs=0 executes each file of a directory once), and
# any problem found there fails the script too.
# Usage: scripts/run-fuzzers.sh [seconds per target]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-20}"
build="$root/build-fuzz"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined" \
  -DSNAG_BUILD_FUZZERS=ON -DSNAG_BUILD_TESTS=OFF -DSNAG_BUILD_BENCHMARKS=OFF \
  -DSNAG_WITH_CUDA=OFF -DSNAG_WITH_CGAL=OFF -DSNAG_WITH_OPENVDB=OFF -DSNAG_WITH_ASSIMP=OFF >/dev/null
formats=(ply obj stl pc2 mdd report manifest)
ninja -C "$build" -j"${JOBS:-2}" "${formats[@]/#/fuzz_}"
status=0
for format in "${formats[@]}"; do
  mkdir -p "$build/corpus/$format"
  echo "== fuzz_$format for ${seconds}s"
  if ! "$build/fuzz/fuzz_$format" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
      -artifact_prefix="$build/crash-$format-" "$build/corpus/$format" "$root/fuzz/corpus/$format" 2>"$build/fuzz_$format.log"; then
    echo "fuzz_$format found a problem: see $build/fuzz_$format.log and $build/crash-$format-*"
    status=1
  fi
  tail -n 1 "$build/fuzz_$format.log"
  degenerate="$root/fuzz/corpus-degenerate/$format"
  if [[ -d "$degenerate" ]]; then
    echo "== fuzz_$format over $(find "$degenerate" -type f | wc -l) degenerate files"
    if ! "$build/fuzz/fuzz_$format" -runs=0 -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
        -artifact_prefix="$build/crash-degenerate-$format-" "$degenerate" 2>"$build/fuzz_${format}_degenerate.log"; then
      echo "fuzz_$format failed on a degenerate file: see $build/fuzz_${format}_degenerate.log"
      status=1
    fi
    tail -n 1 "$build/fuzz_${format}_degenerate.log"
  fi
done
exit $status
