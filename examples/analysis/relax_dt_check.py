#!/usr/bin/env python3
"""relax-60 dt check: compares θ(t) and D/D0(t) of runs that differ only in dt or
precision. For each run against a reference run: the largest |Δθ| (circle fit) at the reference's
row times for t <= 0.5 and for t >= 1 (rows both runs have), and the means ± std of θ (circle
fit, area inversion) and D/D0 over unit windows. Usage:
  examples/analysis/relax_dt_check.py REF_DIR DIR... (each a `sphlab run` output with series.csv)"""
import csv
import statistics as st
import sys


def load(d):
    rows = list(csv.DictReader(open(f"{d}/series.csv")))
    return [(float(r["t"]), float(r["theta_circle_fit"]), float(r["theta_area"]), float(r["spread_factor"])) for r in rows]


def gap(ref, run, keep):
    """Largest |Δθ| at the rows both runs have (same t to 1e-9), t = 0 left out (the circle fit
    of the initial lattice is degenerate)."""
    other = {round(r[0], 9): r[1] for r in run}
    g = [abs(y - other[round(t, 9)]) for (t, y, *_) in ref if t > 0 and keep(t) and round(t, 9) in other]
    return max(g) if g else float("nan")


ref_dir, dirs = sys.argv[1], sys.argv[2:]
ref = load(ref_dir)
t_end = ref[-1][0]
print(f"reference {ref_dir}")
print("| run | max |Δθ| t ≤ 0.5 | max |Δθ| t ≥ 1 |")
print("|---|---|---|")
for d in dirs:
    run = load(d)
    print(f"| {d} | {gap(ref, run, lambda t: t <= 0.5):.3f}° | {gap(ref, run, lambda t: t >= 1.0):.2f}° |")
print()
print("| run | window | θ circle fit | θ area inversion | D/D0 |")
print("|---|---|---|---|---|")
for d in [ref_dir] + dirs:
    run = load(d)
    a = 1.0
    while a + 1.0 <= t_end + 1e-6:
        w = [r for r in run if a <= r[0] <= a + 1.0]
        if w:
            c, ar, dd = ([r[k] for r in w] for k in (1, 2, 3))
            print(f"| {d} | [{a:.0f}, {a + 1:.0f}] | {st.mean(c):.2f} ± {st.pstdev(c):.2f} | {st.mean(ar):.2f} ± {st.pstdev(ar):.2f} | {st.mean(dd):.4f} |")
        a += 1.0
