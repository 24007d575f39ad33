#!/usr/bin/env python3
"""The peak neighbour table of commands.sh: each run's scene, kernel, nx, time reached, status and
`peak_neighbours`, beside the lattice count of the kernel's support (itself included). Reads
*/summary.json beside this file."""
import glob, json, math, os
here = os.path.dirname(os.path.abspath(__file__))
SUPPORT = {"quintic": 3.0, "cubic-spline": 2.0, "wendland-c2": 2.0, "johnson": 2.0, "gaussian": 3.0}

def lattice(radius):
    r = int(math.floor(radius))
    return sum(1 for i in range(-r, r + 1) for j in range(-r, r + 1) if i * i + j * j < radius * radius)

print("| run | kernel, h/Δx | support/Δx | lattice neighbours | t reached (status) | peak neighbours | peak ÷ lattice |")
print("|---|---|---|---|---|---|---|")
for f in sorted(glob.glob(os.path.join(here, "*", "summary.json"))):
    d = json.load(open(f))
    k = d["parameters"]["kernel"]
    s = SUPPORT[k["kind"]] * k["h_ratio"]
    lat = lattice(s)
    peak = d.get("peak_neighbours")
    ratio = f"{peak / lat:.2f}" if peak else "-"
    name = os.path.basename(os.path.dirname(f))
    print(f"| {name} | {k['kind']}, {k['h_ratio']} | {s:.1f} | {lat} | {d['t_final']:.4g} ({d['status']}) | {peak} | {ratio} |")
