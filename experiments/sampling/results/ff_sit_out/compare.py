# Compares two sampled runs' --stats-json documents (before, after) and optionally a full run: usage compare.py BEFORE AFTER [FULL]
import json, sys
b = json.load(open(sys.argv[1])); a = json.load(open(sys.argv[2]))
full = json.load(open(sys.argv[3])) if len(sys.argv) > 3 else None
fv = {}
if full:
    t = full["timing"]
    fv = {"cycles": full["cycles"], "fps": t["fps"], "mrps": t["mrps"], "issue_rate": t["issue_rate"],
          "l1_hit_rate": t["l1_hit_rate"], "l2_hit_rate": t["l2_hit_rate"],
          "dram_bytes": t["memory"]["dram"]["bytes"], "energy_j": t["energy"]["total"]}
sb, sa = b["sampled"], a["sampled"]
print("host s: before %.1f (ff %.1f)  after %.1f (ff %.1f)" % (sb["wall_seconds"], sb["fast_forward_wall_seconds"], sa["wall_seconds"], sa["fast_forward_wall_seconds"]))
print("%-14s %14s %8s %14s %8s %8s %14s %s" % ("metric", "before", "±%", "after", "±%", "move%", "full", "covers(b/a)"))
for m in ["cycles", "issue_rate", "l1_hit_rate", "l2_hit_rate", "dram_bytes", "energy_j"]:
    eb, ea = sb["estimates"][m], sa["estimates"][m]
    hb = (eb["ci95_high"] - eb["ci95_low"]) / 2 / eb["estimate"] * 100
    ha = (ea["ci95_high"] - ea["ci95_low"]) / 2 / ea["estimate"] * 100
    mv = (ea["estimate"] - eb["estimate"]) / eb["estimate"] * 100
    cov = ""
    if m in fv:
        v = fv[m]
        cov = "%s/%s" % (eb["ci95_low"] <= v <= eb["ci95_high"], ea["ci95_low"] <= v <= ea["ci95_high"])
    print("%-14s %14.6g %8.2f %14.6g %8.2f %8.2f %14s %s" % (m, eb["estimate"], hb, ea["estimate"], ha, mv, ("%.6g" % fv[m]) if m in fv else "-", cov))
