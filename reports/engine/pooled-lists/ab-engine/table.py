#!/usr/bin/env python3
"""The A/B table of commands.sh: before (ee99641) ÷ after (9b0b2ff) ms/step (median of a record's
repeats) per variant and N, geometric mean over the rounds with their range. Reads
<label>-r*/records.csv beside this file."""
import csv, glob, math, os
here = os.path.dirname(os.path.abspath(__file__))
rows = {}
for label in ("ee99641", "9b0b2ff"):
    for f in sorted(glob.glob(os.path.join(here, f"{label}-r*", "records.csv"))):
        for r in csv.DictReader(open(f)):
            if r["status"] != "ok" or r["backend"] != "gpu":
                continue
            rows.setdefault((r["variant"], int(r["n"])), {}).setdefault(label, []).append(float(r["ms_per_step_median"]))
print("| variant | N | ee99641, ms/step (median of rounds) | 9b0b2ff | ee99641 ÷ 9b0b2ff, geometric mean (min–max of the rounds) |")
print("|---|---|---|---|---|")
med = lambda x: sorted(x)[len(x) // 2]
for (v, n), d in sorted(rows.items()):
    a, b = d.get("ee99641", []), d.get("9b0b2ff", [])
    ratios = [x / y for x, y in zip(a, b)]
    if ratios:
        g = math.exp(sum(map(math.log, ratios)) / len(ratios))
        print(f"| {v} | {n:,} | {med(a):.1f} | {med(b):.1f} | {g:.2f}× ({min(ratios):.2f}–{max(ratios):.2f}) |")
