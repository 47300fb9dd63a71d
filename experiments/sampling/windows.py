#!/usr/bin/env python3
"""Sets a sampled run's windows beside a full run of the same frame, stratum by stratum.

    experiments/sampling/windows.py FULL.json SAMPLED.json

FULL.json: `trax run ... --stats-interval N --stats-json` (its `timing.intervals`);
SAMPLED.json: the same run with `--sample K` (its `sampled.strata`). For each stratum it
takes the full run's cycles over the stratum's instructions (the intervals' cumulative
instructions, interpolated; the full run counts issued instructions, the sampled run
executed ones, so positions are scaled by issued / (issued + debug ops)) and compares
that stratum's cycles per instruction with its window's: the window's error is the
estimator's error on that stratum. Prints one line per stratum and the weighted sum
(the middle's cycles: what the estimate sums) against the full run's.
"""
import bisect
import json
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    full = json.load(open(sys.argv[1]))
    samp = json.load(open(sys.argv[2]))
    iv = full["timing"]["intervals"]
    if not iv:
        sys.exit(f"{sys.argv[1]}: no timing.intervals (run it with --stats-interval N)")
    strata = samp["sampled"].get("strata")
    if not strata:
        sys.exit(f"{sys.argv[2]}: no sampled.strata (a sampled run of this trax or later)")
    issued = full["instructions"]
    scale = issued / (issued + full["timing"]["debug_ops"])
    xs, cs = [0.0], [0.0]
    for i in iv:
        xs.append(xs[-1] + i["instructions"])
        cs.append(i["end_cycle"])

    def full_rays(c0, c1):
        """The full run's mean rays in flight over cycles c0..c1 (its intervals')."""
        num = den = 0.0
        for i in iv:
            lo, hi = max(c0, i["start_cycle"]), min(c1, i["end_cycle"])
            if hi > lo and i.get("mean_rays_in_flight") is not None:
                num += (hi - lo) * i["mean_rays_in_flight"]
                den += hi - lo
        return num / den if den else float("nan")

    def cycle_at(executed):
        x = executed * scale
        j = min(max(bisect.bisect_left(xs, x), 1), len(xs) - 1)
        x0, x1 = xs[j - 1], xs[j]
        f = 0.0 if x1 == x0 else (x - x0) / (x1 - x0)
        return cs[j - 1] + f * (cs[j] - cs[j - 1])

    print(f"head ends at {strata[0]['start_executed'] / samp['sampled']['executed_instructions']:.1%} "
          f"of the instructions, the tail starts at "
          f"{(strata[-1]['start_executed'] + strata[-1]['executed']) / samp['sampled']['executed_instructions']:.1%}")
    print(f"{'h':>3} {'start':>6} {'share':>6} {'full CPI':>9} {'window CPI':>10} "
          f"{'error':>7} {'rays full':>9} {'window':>7} {'cut':>4}")
    total_exec = samp["sampled"]["executed_instructions"]
    est = truth = 0.0
    errs = []
    for h, s in enumerate(strata):
        a, e = s["start_executed"], s["executed"]
        c0, c1 = cycle_at(a), cycle_at(a + e)
        true_c = c1 - c0
        cpi_full = true_c / e
        cpi_win = s["window_cycles"] / s["window_executed"]
        err = cpi_win / cpi_full - 1
        errs.append(err)
        est += e * cpi_win
        truth += true_c
        print(f"{h:>3} {a / total_exec:>6.1%} {e / total_exec:>6.1%} {cpi_full:>9.4f} "
              f"{cpi_win:>10.4f} {err:>+7.2%} {full_rays(c0, c1):>9.0f} "
              f"{s['window_rays_in_flight']:>7.0f} "
              f"{'cut' if s['cut'] else '':>4}")
    mean = sum(errs) / len(errs)
    print(f"middle: windows sum to {est:.0f} cycles, the full run has {truth:.0f} there "
          f"({est / truth - 1:+.2%}); mean per-stratum error {mean:+.2%}, "
          f"{sum(1 for x in errs if x > 0)}/{len(errs)} strata high")
    est_total = samp["sampled"]["estimates"]["cycles"]["estimate"]
    print(f"whole run: estimate {est_total:.0f}, full {full['cycles']} "
          f"({est_total / full['cycles'] - 1:+.2%})")
    # The head and tail are simulated in detail (the tail after a fast-forward): what the
    # estimate has outside the middle against the full run's cycles there.
    out_est, out_full = est_total - est, full["cycles"] - truth
    print(f"outside the middle (head + tail): estimate {out_est:.0f}, full {out_full:.0f} "
          f"({out_est / out_full - 1:+.2%}; {(out_est - out_full) / full['cycles']:+.2%} "
          f"of the whole run)")


if __name__ == "__main__":
    main()
