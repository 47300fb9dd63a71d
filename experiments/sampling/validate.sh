#!/usr/bin/env bash
# Validation of sampled timing simulation (`trax run --sample`): every (kernel, scene,
# chip) point runs in full (timing, detailed DRAM) and sampled; summarize.py then sets each
# estimate and its 95% interval beside the full run's value.
#
#   experiments/sampling/validate.sh [OUT_DIR]      (default: results/sampling)
#
# 3 kernels x 4 scenes x 2 chips = 24 points, 128x128, one host thread each, one point at
# a time (wall times are compared). Needs a release build (`cargo build --release`); runs
# from the repository root; scenes from ../shared/scenes as the tests read them.
set -euo pipefail
cd "$(dirname "$0")/../.."
TRAX=${TRAX:-target/release/trax}
OUT=${1:-results/sampling}
# Frames of 0.5-3 M cycles: 20 windows of 1000 + 4000 cycles (the defaults, 2000 + 8000,
# suit thesis-scale frames of tens of millions).
SAMPLE=(--sample "${WINDOWS:-20}" --sample-warmup "${WARMUP:-1000}" --sample-window "${WINDOW:-4000}")
mkdir -p "$OUT/points"
SCENES=(cornell ../shared/scenes/sponza/sponza.obj box:../shared/scenes/dragon/dragon-100k.obj hairball:20000)
SCENE_NAMES=(cornell sponza dragon_box hairball)
# name | trax run chip flags
CHIPS=(
  "baseline|--config baseline --tms 16 --l2s 2"
  "strata_1ch|--config strata --tms 16 --l2s 1 --set memory.dram.detailed.channels=1"
)
# name | kernel | the register it takes pixels from
KERNELS=(
  "pathtracer|examples/pathtracer.rs|255"
  "ao|examples/ao.rs|255"
  "raycast|examples/raycast.rs|0"
)
for k in "${KERNELS[@]}"; do
  IFS='|' read -r kname kfile kreg <<<"$k"
  for i in "${!SCENES[@]}"; do
    for c in "${CHIPS[@]}"; do
      IFS='|' read -r cname cflags <<<"$c"
      id="${kname}-${SCENE_NAMES[$i]}-${cname}"
      # shellcheck disable=SC2086
      common=("$kfile" --scene "${SCENES[$i]}" --width 128 --height 128 --host-threads 1 $cflags)
      if [ ! -s "$OUT/points/$id-full.json" ]; then
        t0=$(date +%s.%N)
        "$TRAX" run "${common[@]}" --stats-json "$OUT/points/$id-full.json" \
          -o "$OUT/points/$id-full.png" 2>"$OUT/points/$id-full.err"
        t1=$(date +%s.%N)
        echo "$t0 $t1" | awk '{print $2 - $1}' >"$OUT/points/$id-full.wall"
      fi
      if [ ! -s "$OUT/points/$id-sampled.json" ]; then
        "$TRAX" run "${common[@]}" "${SAMPLE[@]}" --sample-counter "$kreg" \
          --stats-json "$OUT/points/$id-sampled.json" -o "$OUT/points/$id-sampled.png" \
          2>"$OUT/points/$id-sampled.err" || echo "$id: sampled run failed (see $id-sampled.err)"
      fi
      if cmp -s "$OUT/points/$id-full.png" "$OUT/points/$id-sampled.png"; then
        echo same >"$OUT/points/$id.image"
      else
        echo differs >"$OUT/points/$id.image"
      fi
      echo "$id done"
    done
  done
done
python3 experiments/sampling/summarize.py "$OUT"
