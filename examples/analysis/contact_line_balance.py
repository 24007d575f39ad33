#!/usr/bin/env python3
"""A relax-60 contact line's balance against its end angle (reports/validation/relax-60/mode-a-check/README.md, reports/validation/convergence/balance/).
For each relax-60 run: the
circle-fit angle averaged over t in [T0, T1] of its series, and X, the x-force of the wall
pairs on the fluid in `sphlab forces`' window around the contact point at the run's last
snapshot, or the mean over its last K snapshots with LAST=K (sum over pressure, viscous and
surface stress, liquid and gas). The fluid side of a
Mode A wall band carries half of its tension (tests/force_balance.rs), so the balance
predicts sigma_LG cos(theta) = (sigma_GS - sigma_LS)/2 + X; the table gives both sides. The
snapshots are git-ignored: this needs the runs on the machine that made them. Mode A runs
(`contact.mode = "a"`) give that table; Mode B runs, which have no wall tensions, give cos(theta),
X and X/(sigma_LG cos(theta)), the part of the liquid-gas pull the wall pairs at the line hold.
Usage:
  [LAST=K] examples/analysis/contact_line_balance.py NX T0 T1 RUN [RUN ...]   (SPHLAB=binary, default target/release/sphlab)"""
import csv
import json
import math
import os
import subprocess
import sys

nx, t0, t1 = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
sphlab = os.environ.get("SPHLAB", "target/release/sphlab")
last = os.environ.get("LAST", "1")
head = False
for run in sys.argv[4:]:
    par = json.load(open(f"{run}/summary.json"))["parameters"]
    sigma = par["surface_tension"]["sigma"]
    sls, sgs, p_b = par["contact"]["sigma_ls"], par["contact"]["sigma_gs"], par["phases"][0]["p_b"]
    rows = list(csv.DictReader(open(f"{run}/series.csv")))
    th = [float(r["theta_circle_fit"]) for r in rows if t0 - 1e-9 <= float(r["t"]) <= t1 + 1e-9 and r["theta_circle_fit"]]
    theta = sum(th) / len(th)
    md = subprocess.run([sphlab, "--threads", "1", "forces", run, "--last", last], check=True, capture_output=True, text=True).stdout
    along = md.split("## x (along")[1].split("## y")[0]
    x_wall = sum(float(line.split("|")[5]) for line in along.splitlines() if line.startswith("| both |") and "**all**" not in line)
    c = math.cos(math.radians(theta))
    name = run.rstrip("/").split("/")[-1]
    mode_a = par["contact"]["mode"] == "a"
    if not head:
        if mode_a:
            print("| run | nx | σ_LS | σ_GS | p_b | θ circle fit | cos θ | X (wall pairs at the line) | ½(σ_GS − σ_LS) + X | residual |")
            print("|---|---|---|---|---|---|---|---|---|---|")
        else:
            print("| run | nx | p_b | θ circle fit | cos θ | X (wall pairs at the line) | X / (σ_LG cos θ) |")
            print("|---|---|---|---|---|---|---|")
        head = True
    if mode_a:
        pred = (0.5 * (sgs - sls) + x_wall) / sigma
        print(f"| `{name}` | {nx} | {sls:g} | {sgs:g} | {p_b:g} | {theta:.2f}° | {c:+.3f} | {x_wall:+.3f} | {pred:+.3f} | {c - pred:+.3f} |")
    else:
        print(f"| `{name}` | {nx} | {p_b:g} | {theta:.2f}° | {c:+.3f} | {x_wall:+.3f} | {x_wall / (sigma * c):.3f} |")
