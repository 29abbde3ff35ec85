#!/usr/bin/env bash
# Installs what is needed, builds snag, and scans the bundled sample cache:
# a baked cloth over a rising sphere (samples/cloth_ball), as two point caches
# with their topology meshes. Writes report.jsonl and prints the summary.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
sample=samples/cloth_ball
build/tools/snag-info "$sample/cloth.pc2" -t "$sample/cloth_rest.obj" "$sample/body.pc2" -t "$sample/body_rest.obj"
# --fail-on 0: finding collisions is the point of the demo, not a failure.
build/tools/snag-scan "$sample/cloth.pc2" -t "$sample/cloth_rest.obj" "$sample/body.pc2" -t "$sample/body_rest.obj" \
  --report report.jsonl --fail-on 0
echo "demo.sh: the report is in report.jsonl"
