#!/usr/bin/env python3
"""sessile-90 quietness check: over the snapshots of RUN with t in [T0, T1], the mean
liquid kinetic energy, the mean-flow wall shear (signed u/(y - y_w) of first-row fluid particles,
averaged per bin of 1/20 of the wall, then its magnitude: the validate case's
`peak mean-flow wall shear rate`), the same with |u/(y - y_w)|, and the max normal deviation of
examples/analysis/normal_deviation_check.py. Usage:
  examples/analysis/sessile_flow_check.py NX DT T0 T1 RUN [RUN ...]   (`sphlab run sessile-90` outputs with snapshots)"""
import csv
import glob
import os
import re
import subprocess
import sys

nx, dt, t0, t1 = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
dx = 0.5 / nx
here = os.path.dirname(os.path.abspath(__file__))
print("| run | snapshots | mean liquid KE | peak mean-flow shear | peak mean |shear| | max normal deviation: median of the maxima | mean 90th pct | mean median |")
print("|---|---|---|---|---|---|---|---|")
for run in sys.argv[5:]:
    s, a, n, ke = [0.0] * 20, [0.0] * 20, [0] * 20, []
    for f in sorted(glob.glob(f"{run}/particles_*.csv")):
        t = int(f.rsplit("_", 1)[1][:-4]) * dt
        if not (t0 - 1e-9 <= t <= t1 + 1e-9):
            continue
        k = 0.0
        for r in csv.DictReader(open(f)):
            ph, x, y, vx, vy = int(r["phase"]), float(r["x"]), float(r["y"]), float(r["vx"]), float(r["vy"])
            if ph == 0:
                k += 0.5 * (vx * vx + vy * vy) * dx * dx  # rho = 1, particle volume dx^2
            if ph > 1 or not (0 < y <= 1.2 * dx) or not (0 <= x <= 0.5):
                continue
            b = min(int(x / 0.5 * 20), 19)
            s[b] += vx / y
            a[b] += abs(vx / y)
            n[b] += 1
        ke.append(k)
    flow = max(abs(s[b] / n[b]) for b in range(20) if n[b])
    noisy = max(a[b] / n[b] for b in range(20) if n[b])
    nd = subprocess.run(
        [sys.executable, os.path.join(here, "normal_deviation_check.py"), run, str(nx), str(dt), str(t0), str(t1)],
        capture_output=True, text=True).stdout.strip().splitlines()[-1]
    q = re.findall(r"(?:maxima|percentile|median) ([0-9.]+)", nd)
    print(f"| {os.path.basename(run.rstrip('/'))} | {len(ke)} | {sum(ke) / len(ke):.2e} | {flow:.3f} | {noisy:.3f} | {q[0]}° | {q[1]}° | {q[2]}° |")
