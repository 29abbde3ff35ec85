#!/usr/bin/env bash
# Rebakes the bundled samples with Blender (headless) into samples/ and the
# Blender-exported animated test files into tests/io_assimp/data/ and
# tests/real_assets/data/.
#   scripts/make-samples.sh
# Needs `blender` 3.4 on PATH (or BLENDER=...) and, for its glTF and FBX
# exporters, numpy for Blender's Python (Debian: python3-numpy).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
blender="${BLENDER:-blender}"
"$blender" -b --factory-startup --python "$root/samples/bake_cloth.py" -- "$root/samples/cloth_ball"
"$blender" -b --factory-startup --python "$root/tests/io_assimp/export_rig.py" -- "$root/tests/io_assimp/data"
"$blender" -b --factory-startup --python "$root/tests/real_assets/make_real_assets.py" -- "$root/tests/real_assets/data"
# A coarse self-colliding cloth lying bunched in a funnel (frames 33-44),
# for the broad phase's brute-force oracle on tight contact
# (tests/pipeline/broad_phase_sample_test.cpp).
"$blender" -b --factory-startup --python "$root/scripts/bake_cloth_cache.py" -- "$root/tests/real_assets/data/cloth_funnel" \
  --cells 32 --frames 44 --body funnel --self-collision --keep-from 33
