#!/usr/bin/env bash
# Rebakes the bundled samples with Blender (headless) into samples/ and the
# Blender-exported animated test files into tests/io_assimp/data/.
#   scripts/make-samples.sh            (needs `blender` 3.4 on PATH)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
blender="${BLENDER:-blender}"
"$blender" -b --factory-startup --python "$root/samples/bake_cloth.py" -- "$root/samples/cloth_ball"
if [ -f "$root/samples/export_rig.py" ]; then
  "$blender" -b --factory-startup --python "$root/samples/export_rig.py" -- "$root/tests/io_assimp/data"
fi
