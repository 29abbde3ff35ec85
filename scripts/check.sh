#!/usr/bin/env bash
# Installs what is needed, builds snag with its tests, runs each fuzzer briefly,
# runs the whole test suite through ctest (GPU tests skip without a GPU), and
# then the CPU tests again in a second build with AddressSanitizer and
# UndefinedBehaviorSanitizer (scripts/sanitizer-build.sh, build-sanitize/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
if [ -x scripts/run-fuzzers.sh ]; then
  bash scripts/run-fuzzers.sh
fi
bash scripts/build.sh -DSNAG_BUILD_TESTS=ON
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 900
bash scripts/sanitizer-build.sh
ctest --test-dir build-sanitize --output-on-failure --parallel "$(nproc)" --timeout 1800 -L cpu
