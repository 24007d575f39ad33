#!/usr/bin/env python3
"""Analysis of examples/analysis/rest_convergence.sh: per resolution the drop at rest's Laplace
jump error (last snapshot, t = 1), spurious speed (mean of the max fluid speed over t ∈ [0.5, 1],
after the start transient a jittered lattice adds) and density error (max over t ∈ [0.5, 1])
under the capillary rule, the lattice start beside
the mean ± standard deviation of the jittered realisations, and the observed order of each
between successive resolutions (from the realisation means; log of the ratio over log of the
resolution ratio). Prints a markdown table (stdlib only).
Usage: examples/analysis/rest_convergence.py RUNDIR"""
import math, os, statistics, sys

sys.path.insert(0, os.path.dirname(__file__))
from capillary_rule import LAPLACE, R, rest, status  # noqa: E402
from pb_sweep import series  # noqa: E402

LATE = (0.5, 1.0)

NXS = [24, 30, 36, 45, 60]
SEEDS = [1, 2, 3]


def point(d, nx):
    st, _ = status(d)
    if st != "ok":
        return None
    jump = rest(d, "quintic", nx)[0]
    late = [r for r in series(d) if LATE[0] <= r["t"] <= LATE[1]]
    vmax = statistics.mean(r["max_speed"] for r in late)
    derr = max(r["max_density_error"] for r in late)
    return {"jump_err": (jump - LAPLACE) / LAPLACE, "vmax": vmax, "derr": derr}


def fmt(v, prec):
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.{prec}f}"


def main():
    runs = sys.argv[1]
    table, means = [], {}
    for nx in NXS:
        lat = point(f"{runs}/rest-nx{nx}-seed0", nx)
        real = [p for p in (point(f"{runs}/rest-nx{nx}-seed{s}", nx) for s in SEEDS) if p]
        row = [nx, f"{R * nx / 0.5:.2f}"]
        for key, prec in [("jump_err", 4), ("vmax", 4), ("derr", 4)]:
            vals = [p[key] for p in real]
            m = statistics.mean(vals) if vals else None
            sd = statistics.stdev(vals) if len(vals) > 1 else None
            means.setdefault(key, {})[nx] = m
            spread = "—"
            if len(vals) > 1:
                spread = f"{fmt(m, prec)} ± {fmt(sd, prec)} (n = {len(vals)})"
            elif vals:
                spread = f"{fmt(m, prec)} (n = 1)"
            row += [fmt(lat[key] if lat else None, prec), spread]
        table.append(row)
    print("| nx | R/Δx | jump error, lattice | jump error, jittered | max speed (mean over t ∈ [0.5, 1]), lattice "
          "| jittered | max density error (t ∈ [0.5, 1]), lattice | jittered |")
    print("|---|---|---|---|---|---|---|---|")
    for r in table:
        print("| " + " | ".join(str(c) for c in r) + " |")
    print()
    print("Observed order p (|e| ∝ Δx^p) from the jittered means, between successive resolutions:")
    for key in ["jump_err", "vmax", "derr"]:
        ps = []
        for a, b in zip(NXS, NXS[1:]):
            ea, eb = means[key].get(a), means[key].get(b)
            if ea and eb:
                ps.append(f"{a}→{b}: {math.log(abs(ea) / abs(eb)) / math.log(b / a):.2f}")
        print(f"* {key}: " + ", ".join(ps))


if __name__ == "__main__":
    main()
