#!/usr/bin/env bash
# Configures and builds the CPU test suite with AddressSanitizer and
# UndefinedBehaviorSanitizer in build-sanitize/ (no CUDA, no benchmarks): any
# invalid access, leak or undefined behaviour ends the test that caused it.
# Optimised at -O1, the level AddressSanitizer's documentation recommends:
# the CGAL-heavy units compile in about half the time they take at -O3 with
# the sanitizers (validate/exact_ccd.cpp: 33 s against 72 s), and that build
# was most of the check's time.
# Extra arguments go to cmake's configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g1"
if [ ! -f build-sanitize/CMakeCache.txt ]; then
  cmake -S . -B build-sanitize "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
    -DSNAG_WITH_CUDA=OFF -DSNAG_BUILD_TESTS=ON -DSNAG_BUILD_BENCHMARKS=OFF "$@"
else
  cmake -S . -B build-sanitize "$@" >/dev/null
fi
cmake --build build-sanitize --parallel "$(nproc)"
