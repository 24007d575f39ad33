#!/usr/bin/env python3
"""Pressure at a relax-60 contact line (reports/validation/relax-60/mode-a-check):
over the snapshots at t >= T0 of each run, the lowest fluid pressure within 3Δx of the contact
point (the outermost first-row liquid particle + Δx/2, on the wall), also relative to p_b, and
the mean first-row gas pressure's deficit against the gas interior (y > 0.35, x < 0.3).
Snapshots are git-ignored: the runs must have been made on this machine. Usage:
  examples/analysis/contact_line_pressure.py NX T0 RUN [RUN ...]   (`sphlab run relax-60` outputs)"""
import csv, glob, json, math, sys
nx, t0 = int(sys.argv[1]), float(sys.argv[2]); dx = 0.5 / nx
for run in sys.argv[3:]:
    pb = json.load(open(run + '/summary.json'))['parameters']['phases'][0]['p_b']
    series = {int(r['step']): float(r['t']) for r in csv.DictReader(open(run + '/series.csv'))}
    mins, gdef = [], []
    for f in sorted(glob.glob(run + '/particles_*.csv')):
        step = int(f.split('_')[-1].split('.')[0])
        if series.get(step, -1) < t0:
            continue
        r = [p for p in csv.DictReader(open(f)) if p['phase'] in ('0', '1')]
        xtp = max(float(p['x']) for p in r if p['phase'] == '0' and float(p['y']) < dx) + dx / 2
        mins.append(min(float(p['p']) for p in r if math.hypot(float(p['x']) - xtp, float(p['y'])) < 3 * dx))
        gint = [float(p['p']) for p in r if p['phase'] == '1' and float(p['y']) > 0.35 and float(p['x']) < 0.3]
        g1 = [float(p['p']) for p in r if p['phase'] == '1' and float(p['y']) < dx and float(p['x']) > xtp + 0.05]
        gdef.append(sum(gint) / len(gint) - sum(g1) / len(g1))
    print(f"{run.rstrip('/').split('/')[-1]}: p_b {pb:g}, snapshots {len(mins)}, min p near the contact line {sum(mins)/len(mins):.1f} ({min(mins):.1f} lowest) = {sum(mins)/len(mins)/pb:.2f} p_b; gas first-row deficit {sum(gdef)/len(gdef):.1f}")
