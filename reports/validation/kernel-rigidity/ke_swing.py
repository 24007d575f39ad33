#!/usr/bin/env python3
"""The shear-wave runs' kinetic-energy swings (README.md): for each run folder, KE(0), each
local minimum of KE followed by a rise, the rise as a fraction of KE(0), and the swing's
period from successive minima (KE swings at twice the wave's frequency)."""
import csv, math, sys

def swings(path):
    rows = list(csv.DictReader(open(f"{path}/series.csv")))
    t = [float(r["t"]) for r in rows]
    ke = [float(r["kinetic_energy"]) for r in rows]
    k0 = ke[0]
    mins = []  # (t_min, ke_min, rise after it / KE0)
    i = 1
    while i < len(ke) - 1:
        if ke[i] < ke[i - 1] and ke[i] <= ke[i + 1]:
            j = i
            while j + 1 < len(ke) and ke[j + 1] >= ke[j]:
                j += 1
            mins.append((t[i], ke[i], (ke[j] - ke[i]) / k0))
            i = j
        i += 1
    return k0, mins

for path in sys.argv[1:]:
    k0, mins = swings(path)
    big = [m for m in mins if m[2] >= 0.01]
    top = max((m[2] for m in mins), default=0.0)
    per = [b[0] - a[0] for a, b in zip(big, big[1:])]
    line = f"{path}: KE0 {k0:.4e}, minima with a rise >= 1 % of KE0: {len(big)}, largest rise {top:.3f} KE0"
    if per:
        p = sum(per[:3]) / len(per[:3])
        w = 2 * math.pi / (2 * p)  # KE period is half the wave's
        line += f", KE swing period {p:.4f} (first {len(per[:3])}), wave omega^2 {w * w:.1f}"
    print(line)
    for m in big[:4]:
        print(f"    min at t = {m[0]:.4f}: KE {m[1]:.3e}, rise {m[2]:.3f} KE0")
