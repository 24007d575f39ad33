#!/usr/bin/env python3
"""The A/B table of commands.sh: full ÷ pooled ms/step (median of a record's repeats) per variant
and N, geometric mean over the rounds with their range. Reads r*/records.csv beside this file."""
import csv, glob, math, os
here = os.path.dirname(os.path.abspath(__file__))
rows = {}
for f in sorted(glob.glob(os.path.join(here, "r*", "records.csv"))):
    for r in csv.DictReader(open(f)):
        if r["status"] != "ok" or r["backend"] != "gpu":
            continue
        base, layout = r["variant"].rsplit(".", 1)
        rows.setdefault((base, int(r["n"])), {}).setdefault(layout, []).append(float(r["ms_per_step_median"]))
print("| variant | N | full, ms/step (median of rounds) | pooled | full ÷ pooled, geometric mean (min–max of the rounds) |")
print("|---|---|---|---|---|")
for (base, n), d in sorted(rows.items()):
    full, pooled = d.get("full", []), d.get("pooled", [])
    ratios = [a / b for a, b in zip(full, pooled)]
    if not ratios:
        continue
    g = math.exp(sum(map(math.log, ratios)) / len(ratios))
    med = lambda x: sorted(x)[len(x) // 2]
    print(f"| {base} | {n:,} | {med(full):.1f} | {med(pooled):.1f} | {g:.2f}× ({min(ratios):.2f}–{max(ratios):.2f}) |")
