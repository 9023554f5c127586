#!/bin/sh
# Renders the reference talk's figures (Andersen 2013) from fresh runs:
#   * the colliding discs as deformed voxels with the checker pattern, every frame;
#   * the cantilever's shear stress from the raw particle stress and from the smoothed
#     particle stress (sigma_p^s = sum_i sigma_i Phi_ip).
# Usage: scripts/render_talk_figures.sh [OUT_DIR]   (default results/figures; talus from
# $TALUS, default build/talus). Earlier runs in OUT_DIR are replaced.
set -eu
TALUS=${TALUS:-build/talus}
OUT=${1:-results/figures}
mkdir -p "$OUT"
"$TALUS" run cases/colliding_discs.yaml --out "$OUT/colliding_discs" --force \
  --set output.voxels=true
"$TALUS" render "$OUT/colliding_discs/run.h5" --pattern checker --frame all \
  -o "$OUT/discs_checker.png"
"$TALUS" run cases/cantilever_stress.yaml --out "$OUT/cantilever_stress" --force
"$TALUS" render "$OUT/cantilever_stress/run.h5" --field stress --component xy \
  -o "$OUT/cantilever_shear_raw.png"
"$TALUS" render "$OUT/cantilever_stress/run.h5" --field stress_smoothed --component xy \
  -o "$OUT/cantilever_shear_smoothed.png"
