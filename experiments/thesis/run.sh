#!/usr/bin/env bash
# The deciding runs of the thesis at its own scale (issue 25): the thesis's scenes
# (Sibenik, Conference) on the thesis's chips at 1024x1024, depth 5, and the critical-mass
# curve (the same pairs as the frame grows). Each point is `trax run` with --stats-json;
# `summarize.py` turns the points into the tables of experiments/README.md.
#
#   experiments/thesis/run.sh [OUT_DIR]    (default: results/thesis)
#
# Unattended and resumable: a point whose JSON exists is skipped, so the script can be
# killed and started again. Environment:
#   ONLY=REGEX        only the points whose id matches
#   TRAX=PATH         the trax binary (default target/release/trax)
#   NICE=N            niceness of the runs (default 5)
#   HOST_THREADS=N    host threads per run (default 1)
# Needs a release build; runs from the repository root; scenes from ../shared/scenes.
set -euo pipefail
cd "$(dirname "$0")/../.."
TRAX=${TRAX:-target/release/trax}
OUT=${1:-results/thesis}
ONLY=${ONLY:-.}
NICE=${NICE:-5}
HT=${HOST_THREADS:-1}
S=../shared/scenes
mkdir -p "$OUT/points"

BASE="examples/pathtracer.rs --config baseline-ch5"
STRATA="examples/strata.rs --config strata-plus"
# id | mode (full or sampled) | trax run arguments
POINTS=()
for scene in sibenik conference; do
  obj="$S/$scene/$scene.obj"
  # Table 5.1 at the thesis's size, sampled (a full 1024x1024 frame on 128 TMs is about an
  # hour per run here).
  POINTS+=("t51-$scene-1024-baseline|sampled|$BASE --scene $obj --width 1024 --height 1024 --depth 5")
  POINTS+=("t51-$scene-1024-strata|sampled|$STRATA --scene $obj --width 1024 --height 1024 --depth 5")
done
# The critical-mass curve on Sibenik: both chips as the frame grows, in full detail up to
# 256x256, sampled at 512x512 (1024x1024 is Table 5.1's point above).
for n in 64 128 256 512; do
  obj="$S/sibenik/sibenik.obj"
  mode=full
  [ "$n" -ge 512 ] && mode=sampled
  POINTS+=("mass-sibenik-$n-baseline|$mode|$BASE --scene $obj --width $n --height $n --depth 5")
  POINTS+=("mass-sibenik-$n-strata|$mode|$STRATA --scene $obj --width $n --height $n --depth 5")
done

for p in "${POINTS[@]}"; do
  IFS='|' read -r id mode args <<<"$p"
  [[ $id =~ $ONLY ]] || continue
  base="$OUT/points/$id"
  [ -s "$base.json" ] && continue
  extra=(--stats-interval 10000)
  [ "$mode" = sampled ] && extra=(--sample 20)
  # shellcheck disable=SC2086
  if nice -n "$NICE" /usr/bin/time -f "%e %U %S" -o "$base.time" "$TRAX" run $args \
      "${extra[@]}" --host-threads "$HT" --stats-json "$base.json.tmp" -o "$base.png" \
      >"$base.out" 2>"$base.err"; then
    mv "$base.json.tmp" "$base.json"
    echo "$(date '+%F %T') $id $mode done"
  else
    echo "$(date '+%F %T') $id $mode FAILED (see $base.err)"
  fi
done
