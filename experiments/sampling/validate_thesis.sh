#!/usr/bin/env bash
# Validation of sampled timing simulation at the thesis's scale: 128-TM chips (and 32-TM
# slices of them), the streaming path tracer (examples/strata.rs) under both schedule
# policies and the plain kernels, each point run in full (timing) and sampled with the
# defaults; summarize.py then sets each estimate and its 95% interval beside the full
# run's value.
#
#   experiments/sampling/validate_thesis.sh [OUT_DIR]    (default: results/sampling_thesis)
#
# Unattended and resumable: a point's run is skipped when its JSON exists, so the script
# can be stopped (kill it) and started again. Environment:
#   PHASE=full|sampled|both   which runs to do (default both; full runs do not depend on
#                             the sampling code, so they can start first)
#   ONLY=REGEX                only the points whose id matches
#   TRAX=PATH                 the trax binary (default target/release/trax)
#   NICE=N                    niceness of the runs (default 10)
#   HOST_THREADS=N            host threads per run (default 2)
# Needs a release build; runs from the repository root; scenes from ../shared/scenes.
set -euo pipefail
cd "$(dirname "$0")/../.."
TRAX=${TRAX:-target/release/trax}
OUT=${1:-results/sampling_thesis}
PHASE=${PHASE:-both}
ONLY=${ONLY:-.}
NICE=${NICE:-10}
HT=${HOST_THREADS:-2}
S=../shared/scenes
mkdir -p "$OUT/points"

# id | trax run arguments (kernel, scene, chip, frame)
POINTS=(
  # Streaming, 32-TM slices of STRaTA+ (the full GDDR5 system), 128x128, depth 5.
  "strata-sibenik-128-32tm-fullest|examples/strata.rs --scene $S/sibenik/sibenik.obj --config strata-plus --tms 32 --width 128 --height 128 --depth 5 --set stream_memory.schedule=fullest"
  "strata-sibenik-128-32tm-claimed|examples/strata.rs --scene $S/sibenik/sibenik.obj --config strata-plus --tms 32 --width 128 --height 128 --depth 5 --set stream_memory.schedule=claimed"
  "strata-conference-128-32tm-fullest|examples/strata.rs --scene $S/conference/conference.obj --config strata-plus --tms 32 --width 128 --height 128 --depth 5 --set stream_memory.schedule=fullest"
  "strata-conference-128-32tm-claimed|examples/strata.rs --scene $S/conference/conference.obj --config strata-plus --tms 32 --width 128 --height 128 --depth 5 --set stream_memory.schedule=claimed"
  "strata-dragonbox-128-32tm-fullest|examples/strata.rs --scene box:$S/dragon/dragon-100k.obj --config strata-plus --tms 32 --width 128 --height 128 --depth 5 --set stream_memory.schedule=fullest"
  "strata-dragonbox-128-32tm-claimed|examples/strata.rs --scene box:$S/dragon/dragon-100k.obj --config strata-plus --tms 32 --width 128 --height 128 --depth 5 --set stream_memory.schedule=claimed"
  # Streaming, the 128-TM STRaTA+ chip, 256x256, depth 5.
  "strata-sibenik-256-fullest|examples/strata.rs --scene $S/sibenik/sibenik.obj --config strata-plus --width 256 --height 256 --depth 5 --set stream_memory.schedule=fullest"
  "strata-sibenik-256-claimed|examples/strata.rs --scene $S/sibenik/sibenik.obj --config strata-plus --width 256 --height 256 --depth 5 --set stream_memory.schedule=claimed"
  "strata-conference-256-fullest|examples/strata.rs --scene $S/conference/conference.obj --config strata-plus --width 256 --height 256 --depth 5 --set stream_memory.schedule=fullest"
  "strata-conference-256-claimed|examples/strata.rs --scene $S/conference/conference.obj --config strata-plus --width 256 --height 256 --depth 5 --set stream_memory.schedule=claimed"
  "strata-dragonbox-256-fullest|examples/strata.rs --scene box:$S/dragon/dragon-100k.obj --config strata-plus --width 256 --height 256 --depth 5 --set stream_memory.schedule=fullest"
  "strata-dragonbox-256-claimed|examples/strata.rs --scene box:$S/dragon/dragon-100k.obj --config strata-plus --width 256 --height 256 --depth 5 --set stream_memory.schedule=claimed"
  # Plain kernels on the 128-TM chips.
  "pathtracer-sibenik-256-ch3|examples/pathtracer.rs --scene $S/sibenik/sibenik.obj --config baseline-ch3 --width 256 --height 256 --depth 5"
  "pathtracer-sibenik-1024-ch3|examples/pathtracer.rs --scene $S/sibenik/sibenik.obj --config baseline-ch3 --width 1024 --height 1024 --depth 5"
  "pathtracer-conference-1024-ch5|examples/pathtracer.rs --scene $S/conference/conference.obj --config baseline-ch5 --width 1024 --height 1024 --depth 5"
  "raycast-sibenik-1024-ch5|examples/raycast.rs --scene $S/sibenik/sibenik.obj --config baseline-ch5 --width 1024 --height 1024"
  "ao-sponza-1024-ch5|examples/ao.rs --scene $S/sponza/sponza.obj --config baseline-ch5 --width 1024 --height 1024"
  "strata-sibenik-1024-claimed|examples/strata.rs --scene $S/sibenik/sibenik.obj --config strata-plus --width 1024 --height 1024 --depth 5 --set stream_memory.schedule=claimed"
)

run() { # id kind args...
  local id=$1 kind=$2
  shift 2
  local base="$OUT/points/$id-$kind"
  [ -s "$base.json" ] && return 0
  # Host time: wall, user and system CPU seconds (on a shared machine the CPU seconds
  # are the comparable figure).
  if nice -n "$NICE" /usr/bin/time -f "%e %U %S" -o "$base.time" "$TRAX" run "$@" \
      --host-threads "$HT" --stats-json "$base.json.tmp" -o "$base.png" >"$base.out" \
      2>"$base.err"; then
    mv "$base.json.tmp" "$base.json"
    echo "$(date '+%F %T') $id $kind done"
  else
    echo "$(date '+%F %T') $id $kind FAILED (see $base.err)"
  fi
}

for p in "${POINTS[@]}"; do
  IFS='|' read -r id args <<<"$p"
  [[ $id =~ $ONLY ]] || continue
  # shellcheck disable=SC2086
  if [ "$PHASE" != sampled ]; then
    run "$id" full $args --stats-interval 10000
  fi
  if [ "$PHASE" != full ]; then
    # shellcheck disable=SC2086
    run "$id" sampled $args --sample 20
  fi
  if [ -s "$OUT/points/$id-full.png" ] && [ -s "$OUT/points/$id-sampled.png" ]; then
    if cmp -s "$OUT/points/$id-full.png" "$OUT/points/$id-sampled.png"; then
      echo same >"$OUT/points/$id.image"
    else
      echo differs >"$OUT/points/$id.image"
    fi
  fi
done
if [ "$PHASE" != full ]; then
  python3 experiments/sampling/summarize.py "$OUT" || true
fi
