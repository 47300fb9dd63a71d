#!/usr/bin/env python3
"""L1 and L2 loads by memory region (issue 25): the points of results/regions/run.sh.

    experiments/thesis/regions.py [RUN_DIR...]   (default: results/regions/*)

For each point (RUN_DIR/ID.json, a full-detail `trax run --stats-json`) writes a compact
summary, experiments/results/regions/RUN-ID.json (totals, stream statistics, both caches'
rows by region), and prints a markdown table per point: per region its loads, strict and
merged-as-hit hit rates and its share of the L1's strict misses, of the requests the L1
sent on, and of the L2's misses.
"""
import glob
import json
import os
import sys

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
OUT = os.path.join(ROOT, "experiments", "results", "regions")


def pct(a, b):
    return 100.0 * a / b if b else 0.0


def table(doc):
    t = doc["timing"]
    m = t["memory"]
    l1 = {r["region"]: r for r in m["l1_by_region"]}
    l2 = {r["region"]: r for r in m["l2_by_region"]}
    miss = sum(r["misses"] for r in l1.values())
    sent = sum(r["misses"] - r["merged"] for r in l1.values())
    miss2 = sum(r["misses"] for r in l2.values())
    rows = ["| region | L1 loads | L1 hit % strict / merged | share of L1 misses strict / sent | L2 hit % | share of L2 misses |",
            "|---|---:|---:|---:|---:|---:|"]
    order = sorted(l1, key=lambda k: -l1[k]["misses"])
    for k in order:
        r = l1[k]
        loads = r["hits"] + r["misses"]
        if loads == 0:
            continue
        r2 = l2.get(k, {"hits": 0, "misses": 0})
        rows.append("| %s | %d | %.1f / %.1f | %.1f / %.1f | %.1f | %.1f |" % (
            k, loads, pct(r["hits"], loads), pct(r["hits"] + r["merged"], loads),
            pct(r["misses"], miss), pct(r["misses"] - r["merged"], sent),
            pct(r2["hits"], r2["hits"] + r2["misses"]), pct(r2["misses"], miss2)))
    # Treelet data: the BVH nodes, and the nodes with the triangles (triangle treelets).
    for names in (["bvh_nodes"], ["bvh_nodes", "triangles"]):
        h = sum(l1[n]["hits"] for n in names if n in l1)
        mg = sum(l1[n]["merged"] for n in names if n in l1)
        loads = sum(l1[n]["hits"] + l1[n]["misses"] for n in names if n in l1)
        rows.append("| **%s** | %d | %.1f / %.1f | | | |" % (" + ".join(names), loads,
                                                            pct(h, loads), pct(h + mg, loads)))
    return "\n".join(rows)


def main():
    dirs = sys.argv[1:] or sorted(glob.glob(os.path.join(ROOT, "results", "regions", "*-*")))
    os.makedirs(OUT, exist_ok=True)
    for d in dirs:
        run = os.path.basename(d.rstrip("/"))
        for f in sorted(glob.glob(os.path.join(d, "*.json"))):
            doc = json.load(open(f))
            t = doc["timing"]
            pid = os.path.basename(f)[:-5]
            keep = {
                "point": f"{run}-{pid}",
                "inputs": doc["inputs"],
                "chip": doc["chip"]["name"],
                "cycles": doc["cycles"],
                "l1_hit_rate": t["l1_hit_rate"],
                "l1_hit_rate_merged_as_hits": t["l1_hit_rate_merged_as_hits"],
                "l2_hit_rate": t["l2_hit_rate"],
                "stream": {k: t["stream"][k] for k in ("reads", "schedules", "rays_per_visit",
                                                        "mean_rays_in_flight")},
                "l1_by_region": t["memory"]["l1_by_region"],
                "l2_by_region": t["memory"]["l2_by_region"],
            }
            with open(os.path.join(OUT, f"{run}-{pid}.json"), "w") as o:
                json.dump(keep, o, indent=1)
            print(f"### {run} {pid}: {doc['cycles']} cycles, L1 {100 * t['l1_hit_rate']:.1f} / "
                  f"{100 * t['l1_hit_rate_merged_as_hits']:.1f}%, "
                  f"{t['stream']['rays_per_visit']:.1f} rays per visit\n")
            print(table(doc))
            print()


if __name__ == "__main__":
    main()
