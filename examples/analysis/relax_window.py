#!/usr/bin/env python3
"""relax-60 equilibrium of a run, averaged over a window of the series: the
circle-fit angle, the area-inversion angle (the cap of the liquid's area and width) and D/D0 at
the wall (first-row D/D0 + (dx/2)·cot(theta)/R0, as validate's relax::wall_spread); also the
angle at t = 0, the largest density error, and over t ≥ 1 the median of the series' kinetic
energy and the mean of its max fluid speed (the motion a formulation leaves in the drop). D0 is the diameter of the scene's 90° half-disc
(R0 = 0.25); a run started from another shape (an equal-area cap,
`examples/analysis/relax_start_angle.sh`) has its series' spread factor x_tp/R rescaled by R/R0, with R
read from the run's summary.json. Usage:
  examples/analysis/relax_window.py NX T0 T1 RUN [RUN ...]   (`sphlab run relax-60` outputs)"""
import csv
import json
import math
import sys

nx, t0, t1 = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
dx, r0 = 0.5 / nx, 0.25
print("| run | θ at t = 0 | rows | θ circle fit (deg) | θ area inversion (deg) | D/D0 at the wall | max density error (whole run) | kinetic energy, median t ≥ 1 | max speed, mean t ≥ 1 |")
print("|---|---|---|---|---|---|---|---|---|")
for run in sys.argv[4:]:
    radius = json.load(open(f"{run}/summary.json"))["parameters"]["shapes"][0]["radius"]
    rows = list(csv.DictReader(open(f"{run}/series.csv")))
    win = [r for r in rows if t0 - 1e-9 <= float(r["t"]) <= t1 + 1e-9 and r["theta_circle_fit"] and r["spread_factor"]]
    th = [float(r["theta_circle_fit"]) for r in win]
    area = [float(r["theta_area"]) for r in win if r["theta_area"]]
    d = [float(r["spread_factor"]) * radius / r0 + 0.5 * dx / (r0 * math.tan(math.radians(float(r["theta_circle_fit"])))) for r in win]
    rho = max(float(r["max_density_error"]) for r in rows)
    start = float(rows[0]["theta_circle_fit"])
    late = [r for r in rows if float(r["t"]) >= 1.0]
    ke = sorted(float(r["kinetic_energy"]) for r in late)
    vmax = [float(r["max_speed"]) for r in late]
    motion = f"{ke[len(ke) // 2]:.2e} | {sum(vmax) / len(vmax):.3f}" if late else "— | —"
    print(f"| {run.rstrip('/').split('/')[-1]} | {start:.1f} | {len(win)} | {sum(th) / len(th):.2f} | {f'{sum(area) / len(area):.2f}' if area else '—'} | {sum(d) / len(d):.3f} | {rho:.4f} | {motion} |")
