#!/usr/bin/env python3
"""relax-60 equilibrium of a run (issue 10): the mean circle-fit angle and D/D0 at the wall
(first-row D/D0 + (dx/2)·cot(theta)/R0, as validate's relax::wall_spread) over a window of the
series, and the largest density error. Usage:
  scripts/relax_window.py NX T0 T1 RUN [RUN ...]   (`sphlab run relax-60` outputs)"""
import csv
import math
import sys

nx, t0, t1 = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
dx, r0 = 0.5 / nx, 0.25
print("| run | rows | θ circle fit (deg) | D/D0 at the wall | max density error (whole run) |")
print("|---|---|---|---|---|")
for run in sys.argv[4:]:
    rows = list(csv.DictReader(open(f"{run}/series.csv")))
    win = [r for r in rows if t0 - 1e-9 <= float(r["t"]) <= t1 + 1e-9 and r["theta_circle_fit"] and r["spread_factor"]]
    th = [float(r["theta_circle_fit"]) for r in win]
    d = [float(r["spread_factor"]) + 0.5 * dx / (r0 * math.tan(math.radians(float(r["theta_circle_fit"])))) for r in win]
    rho = max(float(r["max_density_error"]) for r in rows)
    print(f"| {run.rstrip('/').split('/')[-1]} | {len(win)} | {sum(th) / len(th):.2f} | {sum(d) / len(d):.3f} | {rho:.4f} |")
