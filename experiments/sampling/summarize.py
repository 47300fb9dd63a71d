#!/usr/bin/env python3
"""Sets each sampled run's estimates beside its full run (validate.sh's points) and writes
OUT/results.csv (one row per point and metric) and OUT/summary.txt: the share of
(point, metric) pairs whose 95% interval covers the full value, the mean absolute error
of cycles, and the host-time speed-ups."""
import glob
import json
import os
import sys

out = sys.argv[1]
# metric -> where the full run's value is
FULL = {
    "cycles": lambda d: d["cycles"],
    "fps": lambda d: d["timing"]["fps"],
    "mrps": lambda d: d["timing"]["mrps"],
    "issue_rate": lambda d: d["timing"]["issue_rate"],
    "l1_hit_rate": lambda d: d["timing"]["l1_hit_rate"],
    "l2_hit_rate": lambda d: d["timing"]["l2_hit_rate"],
    "dram_bytes": lambda d: d["timing"]["memory"]["dram"]["bytes"],
    "energy_j": lambda d: d["timing"]["energy"]["total"],
}
# Metrics of the thesis's tables and figures, compared where the sampled run has them
# (runs made before they were estimated lack them).
MORE = {
    "l1_hit_rate_merged_as_hits": lambda d: d["timing"]["l1_hit_rate_merged_as_hits"],
    "l2_hit_rate_merged_as_hits": lambda d: d["timing"]["l2_hit_rate_merged_as_hits"],
    "l2_accesses": lambda d: sum(x["accesses"] for x in d["timing"]["memory"]["l2"]),
    "dram_accesses": lambda d: d["timing"]["memory"]["dram"]["reads"]
    + d["timing"]["memory"]["dram"]["writes"],
    "dram_row_hit_rate": lambda d: d["timing"]["memory"]["dram"]["row_hit_rate"],
    "dram_read_latency_cycles": lambda d: d["timing"]["memory"]["dram"][
        "avg_read_latency_cycles"],
    "energy_dram_j": lambda d: d["timing"]["energy"]["dram"],
    "stream_accesses": lambda d: d["timing"]["stream"]["reads"] + d["timing"]["stream"]["writes"],
    "rays_per_visit": lambda d: d["timing"]["stream"]["rays_per_visit"],
    "mean_rays_in_flight": lambda d: d["timing"]["stream"]["mean_rays_in_flight"],
}


def wall(base):
    """Host wall seconds of a run: BASE.wall (validate.sh) or the first field of BASE.time
    (validate_thesis.sh, /usr/bin/time -f "%e %U %S")."""
    for ext in (".wall", ".time"):
        if os.path.exists(base + ext):
            return float(open(base + ext).read().split()[0])
    return float("nan")

def cpu(base):
    """Host CPU seconds (user + system) of a run from BASE.time (validate_thesis.sh); NaN
    without it. On a shared machine these, not wall seconds, compare two runs."""
    if os.path.exists(base + ".time"):
        f = open(base + ".time").read().split()
        if len(f) >= 3:
            return float(f[1]) + float(f[2])
    return float("nan")

rows, points, cpus = [], [], []
for f in sorted(glob.glob(os.path.join(out, "points", "*-full.json"))):
    pid = os.path.basename(f)[: -len("-full.json")]
    s_path = os.path.join(out, "points", pid + "-sampled.json")
    if not os.path.exists(s_path):
        continue
    full, samp = json.load(open(f)), json.load(open(s_path))
    s = samp["sampled"]
    wall_full = wall(os.path.join(out, "points", pid + "-full"))
    cpus.append((cpu(os.path.join(out, "points", pid + "-full")),
                 cpu(os.path.join(out, "points", pid + "-sampled"))))
    img = os.path.join(out, "points", pid + ".image")
    image = open(img).read().strip() if os.path.exists(img) else "?"
    points.append((pid, wall_full, s["wall_seconds"], image,
                   s["detailed_instructions"] / s["executed_instructions"]))
    more = [(m, g) for m, g in MORE.items() if s["estimates"].get(m)]
    for m, get in list(FULL.items()) + more:
        v = get(full)
        e = s["estimates"][m]
        rows.append({
            "point": pid, "metric": m, "full": v, "estimate": e["estimate"],
            "ci95_low": e["ci95_low"], "ci95_high": e["ci95_high"],
            "rel_error": (e["estimate"] - v) / v if v else 0.0,
            "rel_half_width": e["rel_half_width"],
            "covered": e["ci95_low"] <= v <= e["ci95_high"],
            "flagged": e["note"] is not None,
        })
with open(os.path.join(out, "results.csv"), "w") as w:
    cols = list(rows[0].keys())
    w.write(",".join(cols) + "\n")
    for r in rows:
        w.write(",".join(str(r[c]) for c in cols) + "\n")
with open(os.path.join(out, "points.csv"), "w") as w:
    w.write("point,full_wall_s,sampled_wall_s,speedup,detailed_fraction,image\n")
    for p, wf, ws, img, frac in points:
        w.write(f"{p},{wf:.3f},{ws:.3f},{wf / ws:.2f},{frac:.4f},{img}\n")
cov = sum(r["covered"] for r in rows) / len(rows)
cyc = [abs(r["rel_error"]) for r in rows if r["metric"] == "cycles"]
lines = [
    f"points: {len(points)}; (point, metric) pairs: {len(rows)}",
    f"95% interval covers the full run's value: {100 * cov:.1f}% of pairs",
]
for m in list(FULL) + list(MORE):
    rs = [r for r in rows if r["metric"] == m]
    if not rs:
        continue
    lines.append(
        f"  {m:<12} covered {sum(r['covered'] for r in rs)}/{len(rs)}, "
        f"mean |error| {100 * sum(abs(r['rel_error']) for r in rs) / len(rs):.3f}%, "
        f"max |error| {100 * max(abs(r['rel_error']) for r in rs):.3f}%, "
        f"mean ± {100 * sum(r['rel_half_width'] for r in rs) / len(rs):.3f}%")
lines.append(f"cycles: mean absolute error {100 * sum(cyc) / len(cyc):.3f}%, "
             f"max {100 * max(cyc):.3f}%")
sp = [wf / ws for _, wf, ws, _, _ in points]
lines.append(f"host-time speed-up (full / sampled): mean {sum(sp) / len(sp):.2f}x, "
             f"min {min(sp):.2f}x, max {max(sp):.2f}x")
cs = [a / b for a, b in cpus if a == a and b == b and b > 0]
if cs:
    lines.append(f"host CPU-time speed-up (user + system, full / sampled): mean "
                 f"{sum(cs) / len(cs):.2f}x, min {min(cs):.2f}x, max {max(cs):.2f}x")
lines.append(f"images identical to the full run's: "
             f"{sum(img == 'same' for _, _, _, img, _ in points)}/{len(points)}")
lines.append("misses: " + ", ".join(
    f"{r['point']}:{r['metric']} ({100 * r['rel_error']:+.2f}% vs ±{100 * r['rel_half_width']:.2f}%)"
    for r in rows if not r["covered"]))
open(os.path.join(out, "summary.txt"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
