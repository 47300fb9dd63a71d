#!/usr/bin/env bash
# L1/L2 accesses by memory region: N x N (default 128) depth 5 on a TMS-TM slice (default 16), full detail.
set -u
cd "$(dirname "$0")/../.."
T=${TRAX:-target/release/trax}
S=../shared/scenes
N=${N:-128}; TMS=${TMS:-16}; O=results/regions/$N-$TMS; mkdir -p $O
for p in "sibenik-strata|examples/strata.rs --config strata-plus --scene $S/sibenik/sibenik.obj" \
         "sibenik-baseline|examples/pathtracer.rs --config baseline-ch5 --scene $S/sibenik/sibenik.obj" \
         "conference-strata|examples/strata.rs --config strata-plus --scene $S/conference/conference.obj" \
         "conference-baseline|examples/pathtracer.rs --config baseline-ch5 --scene $S/conference/conference.obj"; do
  IFS='|' read -r id args <<<"$p"
  [ -s "$O/$id.json" ] && continue
  # shellcheck disable=SC2086
  nice -n 10 /usr/bin/time -f "%e %U %S" -o "$O/$id.time" $T run $args --tms $TMS --width $N --height $N --depth 5 \
     --host-threads 1 --stats-json "$O/$id.json.tmp" -o "$O/$id.png" >"$O/$id.out" 2>"$O/$id.err" \
     && mv "$O/$id.json.tmp" "$O/$id.json"
  echo "$(date -u '+%T') $id done rc=$?"
done
