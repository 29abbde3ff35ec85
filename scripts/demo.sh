#!/usr/bin/env bash
# Installs what is needed, builds snag, and scans the bundled sample cache:
# a baked cloth over a rising sphere (samples/cloth_ball), as two point caches
# with their topology meshes. Writes report.jsonl, prints the summary, and
# writes report.html.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
sample=samples/cloth_ball
build/tools/snag-info "$sample/cloth.pc2" -t "$sample/cloth_rest.obj" "$sample/body.pc2" -t "$sample/body_rest.obj"
# --fail-on 0: finding collisions is the point of the demo, not a failure.
build/tools/snag-scan "$sample/cloth.pc2" -t "$sample/cloth_rest.obj" "$sample/body.pc2" -t "$sample/body_rest.obj" \
  --report report.jsonl --fail-on 0
# The page to open in a browser, with the cache read again for the 3D view.
build/tools/snag-report report.jsonl --html report.html \
  --cache "$sample/cloth.pc2" -t "$sample/cloth_rest.obj" --cache "$sample/body.pc2" -t "$sample/body_rest.obj"
echo "demo.sh: the report is in report.jsonl, the page in report.html"
