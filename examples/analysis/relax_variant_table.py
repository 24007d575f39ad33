#!/usr/bin/env python3
"""relax-60 variant table: runs grouped by variant, each variant run at several dt
(different realisations of the stick-slip contact line). Per run the means over the window of
θ (circle fit, area inversion) and D/D0 (series.csv spread_factor); per variant the mean and the
values of its runs. Run directories are named VARIANT_dtDT[-NOTE] and grouped by the part before
"_dt". Usage:
  examples/analysis/relax_variant_table.py T0 T1 DIR...   (each a `sphlab run relax-60` output)"""
import csv
import statistics as st
import sys
from collections import OrderedDict


def window_means(d, lo, hi):
    rows = [r for r in csv.DictReader(open(f"{d}/series.csv")) if lo <= float(r["t"]) <= hi]
    if not rows:
        return None
    return tuple(st.mean(float(r[k]) for r in rows) for k in ("theta_circle_fit", "theta_area", "spread_factor"))


lo, hi = float(sys.argv[1]), float(sys.argv[2])
groups = OrderedDict()
for d in sys.argv[3:]:
    name = d.rstrip("/").split("/")[-1]
    m = window_means(d, lo, hi)
    if m is None:
        print(f"{name}: no rows in [{lo}, {hi}]", file=sys.stderr)
        continue
    groups.setdefault(name.split("_dt")[0], []).append((name, m))
print(f"Window t ∈ [{lo}, {hi}]; analytic θ = 60°, D/D0 = 1.385.\n")
print("| variant | runs | θ circle fit: mean (per run) | θ area: mean (per run) | D/D0: mean (per run) |")
print("|---|---|---|---|---|")
for g, runs in groups.items():
    cols = []
    for k, fmt in ((0, "{:.2f}"), (1, "{:.2f}"), (2, "{:.4f}")):
        vals = [m[k] for _, m in runs]
        cols.append(fmt.format(st.mean(vals)) + " (" + ", ".join(fmt.format(v) for v in vals) + ")")
    print(f"| {g} | {len(runs)} | " + " | ".join(cols) + " |")
