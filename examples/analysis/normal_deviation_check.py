#!/usr/bin/env python3
"""sessile-90 max normal deviation per snapshot (Fig. 4.9), the same selection as
diagnostics::flow::normal_deviations with the validate case's band (fluid particles with
|r − 0.25| ≤ 3Δx, y > 3Δx, |∇C| ≥ 0.3·max; angle between ±∇C and the radial direction from the
origin). Per snapshot in [T0, T1]: the largest angle, and over the snapshots the median of the
maxima and the means of the per-snapshot 90th percentile and median. Usage:
  examples/analysis/normal_deviation_check.py RUN_DIR NX DT T0 T1   (a `sphlab run sessile-90` output with snapshots)"""
import csv
import glob
import math
import statistics as st
import sys

run, nx, dt, t0, t1 = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
dx = 0.5 / nx


def deviations(f):
    fl = []
    for r in csv.DictReader(open(f)):
        x, y, ph, gx, gy = float(r["x"]), float(r["y"]), int(r["phase"]), float(r["gcx"]), float(r["gcy"])
        if ph in (0, 1) and abs(math.hypot(x, y) - 0.25) <= 3 * dx:
            fl.append((x, y, ph, gx, gy))
    gmax = max((math.hypot(p[3], p[4]) for p in fl if p[1] > 3 * dx), default=0.0)
    out = []
    for x, y, ph, gx, gy in fl:
        g, r = math.hypot(gx, gy), math.hypot(x, y)
        if g <= 0 or g < 0.3 * gmax or y <= 3 * dx:
            continue
        s = 1 if ph == 0 else -1
        out.append(math.degrees(math.acos(max(-1.0, min(1.0, s * (gx * x + gy * y) / (g * r))))))
    return sorted(out)


maxima, p90, med, counted = [], [], [], 0
for f in sorted(glob.glob(f"{run}/particles_*.csv")):
    t = int(f.rsplit("_", 1)[1][:-4]) * dt
    if t0 <= t <= t1 + 1e-9:
        d = deviations(f)
        if d:
            maxima.append(d[-1])
            p90.append(d[int(0.9 * len(d))])
            med.append(d[len(d) // 2])
            counted = len(d)
print(f"{run}: {len(maxima)} snapshots in [{t0}, {t1}], {counted} particles counted in the last")
print("per-snapshot max:", ", ".join(f"{m:.1f}" for m in maxima))
print(f"median of the maxima {st.median(maxima):.2f}; mean 90th percentile {st.mean(p90):.2f}; mean median {st.mean(med):.2f}")
