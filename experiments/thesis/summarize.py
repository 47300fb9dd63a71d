#!/usr/bin/env python3
"""Turns experiments/thesis/run.sh's points into OUT/results.csv (one row per point: scene,
chip, size, mode and the metrics, with the 95% interval's half-width of sampled estimates)
and OUT/summary.md: Table 5.1's rows beside the thesis's absolute numbers and the
critical-mass table. `trax plot OUT/results.csv --x size --y METRIC --by chip --where
scene=sibenik` draws the curves.

    python3 experiments/thesis/summarize.py OUT
"""
import glob
import json
import os
import sys

out = sys.argv[1]


def dram(d):
    return d["timing"]["memory"]["dram"]


def stream(d, key):
    """A stream statistic; None on a chip without a stream memory (nothing read from it)."""
    s = d["timing"].get("stream")
    return s[key] if s and s.get("reads") else None


# column (as trax sweep's metrics) -> (value in a full run's JSON, sampled estimate's name)
METRICS = {
    "cycles": (lambda d: d["cycles"], "cycles"),
    "l1_hit_rate": (lambda d: d["timing"]["l1_hit_rate"], "l1_hit_rate"),
    "l1_hit_rate_merged": (lambda d: d["timing"]["l1_hit_rate_merged_as_hits"],
                           "l1_hit_rate_merged_as_hits"),
    "l2_accesses": (lambda d: sum(x["accesses"] for x in d["timing"]["memory"]["l2"]),
                    "l2_accesses"),
    "dram_accesses": (lambda d: dram(d)["reads"] + dram(d)["writes"], "dram_accesses"),
    "dram_row_hit_rate": (lambda d: dram(d)["row_hit_rate"], "dram_row_hit_rate"),
    "dram_read_latency": (lambda d: dram(d)["avg_read_latency_cycles"],
                          "dram_read_latency_cycles"),
    "energy_dram_j": (lambda d: d["timing"]["energy"]["dram"], "energy_dram_j"),
    "energy_j": (lambda d: d["timing"]["energy"]["total"], "energy_j"),
    "energy_memsys_j": (lambda d: d["timing"]["energy"]["l2"] + d["timing"]["energy"]["dram"]
                        + (d["timing"]["energy"].get("stream_memory") or 0.0),
                        "energy_memsys_j"),
    "stream_accesses": (lambda d: (stream(d, "reads") or 0) + (stream(d, "writes") or 0),
                        "stream_accesses"),
    "stream_rays_per_visit": (lambda d: stream(d, "rays_per_visit"), "rays_per_visit"),
    "rays_in_flight": (lambda d: stream(d, "mean_rays_in_flight"), "mean_rays_in_flight"),
}
# Thesis Table 5.1 (1024x1024): accesses (M), row-buffer hit rate (%), average read
# latency (cycles), ms/frame, DRAM energy (J); baseline and STRaTA+.
THESIS = {
    "sibenik": {"baseline": (39, 69, 39, 21, 1.7), "strata": (15, 84, 31, 23, 0.98)},
    "conference": {"baseline": (18, 57, 42, 17, 1.1), "strata": (9, 83, 35, 23, 0.84)},
}

rows = []
for f in sorted(glob.glob(os.path.join(out, "points", "*.json"))):
    pid = os.path.basename(f)[:-5]
    kind, scene, size, chip = pid.split("-")
    d = json.load(open(f))
    s = d.get("sampled")
    row = {"id": pid, "experiment": kind, "scene": scene, "size": int(size), "chip": chip,
           "mode": "sampled" if s else "full", "clock_ghz": d["chip"].get("clock_ghz", 1.0)}
    for col, (get, est) in METRICS.items():
        if s:
            e = s["estimates"].get(est)
            row[col] = e["estimate"] if e else None
            row[col + "_ci95"] = (e["ci95_high"] - e["estimate"]) if e else None
        else:
            try:
                row[col] = get(d)
            except (KeyError, TypeError):
                row[col] = None
            row[col + "_ci95"] = None
    t = os.path.join(out, "points", pid + ".time")
    row["wall_seconds"] = float(open(t).read().split()[0]) if os.path.exists(t) else None
    rows.append(row)
if not rows:
    sys.exit(f"{out}/points: no finished points")

cols = list(rows[0].keys())
with open(os.path.join(out, "results.csv"), "w") as w:
    w.write(",".join(cols) + "\n")
    for r in rows:
        w.write(",".join("" if r[c] is None else str(r[c]) for c in cols) + "\n")


def fmt(r, col, scale=1.0, digits=1, pct=False):
    v = r.get(col)
    if v is None:
        return "-"
    k = 100.0 if pct else scale
    text = f"{v * k:.{digits}f}"
    ci = r.get(col + "_ci95")
    return text + (f" ± {ci * k:.{digits}f}" if ci else "")


lines = ["## Table 5.1 at 1024x1024 (trax; the thesis's value in parentheses)", "",
         "| scene | chip | mode | DRAM accesses (M) | row-buffer hits (%) | read latency "
         "(cycles) | ms/frame | DRAM energy (J) |", "|---|---|---|---|---|---|---|---|"]
for r in rows:
    if r["experiment"] != "t51":
        continue
    th = THESIS.get(r["scene"], {}).get(r["chip"])
    thv = [f" ({x})" for x in th] if th else [""] * 5
    ms = dict(r, ms=r["cycles"] / (r["clock_ghz"] * 1e6),
              ms_ci95=(r["cycles_ci95"] or 0) / (r["clock_ghz"] * 1e6) or None)
    lines.append(
        f"| {r['scene']} | {r['chip']} | {r['mode']} | {fmt(r, 'dram_accesses', 1e-6)}{thv[0]}"
        f" | {fmt(r, 'dram_row_hit_rate', pct=True)}{thv[1]}"
        f" | {fmt(r, 'dram_read_latency', digits=0)}{thv[2]} | {fmt(ms, 'ms')}{thv[3]}"
        f" | {fmt(r, 'energy_dram_j', digits=2)}{thv[4]} |")
lines += ["", "## Critical mass (Sibenik, 128 TMs, depth 5)", "",
          "| size | chip | mode | rays/visit | rays in flight | L1 hits strict (%) | L1 hits "
          "merged (%) | L2 accesses (M) | stream accesses (M) | DRAM accesses (M) | DRAM J |"
          " cycles (M) |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for r in sorted(rows, key=lambda r: (r["scene"], r["size"], r["chip"])):
    lines.append(
        f"| {r['size']}² {r['scene']} | {r['chip']} | {r['mode']} | "
        f"{fmt(r, 'stream_rays_per_visit')} | {fmt(r, 'rays_in_flight', digits=0)} | "
        f"{fmt(r, 'l1_hit_rate', pct=True)} | {fmt(r, 'l1_hit_rate_merged', pct=True)} | "
        f"{fmt(r, 'l2_accesses', 1e-6, 2)} | {fmt(r, 'stream_accesses', 1e-6, 2)} | "
        f"{fmt(r, 'dram_accesses', 1e-6, 2)} | {fmt(r, 'energy_dram_j', digits=3)} | "
        f"{fmt(r, 'cycles', 1e-6, 2)} |")
lines += ["", "## STRaTA+ over the baseline, by frame size (Sibenik)", "",
          "| size | rays/visit | cycles | L2 accesses | DRAM accesses | DRAM energy | memory energy |",
          "|---|---|---|---|---|---|---|"]
by = {(r["scene"], r["size"], r["chip"]): r for r in rows}
for (scene, size, chip), r in sorted(by.items()):
    b = by.get((scene, size, "baseline"))
    if chip != "strata" or not b or scene != "sibenik":
        continue
    ratio = lambda c: f"{r[c] / b[c]:.2f}x" if r.get(c) and b.get(c) else "-"
    lines.append(f"| {size}² | {fmt(r, 'stream_rays_per_visit')} | {ratio('cycles')} | "
                 f"{ratio('l2_accesses')} | {ratio('dram_accesses')} | {ratio('energy_dram_j')} | "
                 f"{ratio('energy_memsys_j')} |")
open(os.path.join(out, "summary.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
