#!/usr/bin/env python3
"""Analysis of examples/analysis/period_convergence.sh: per resolution the oscillating drop's
period (the pb_sweep method: the first two maxima of the 5-sample moving average of centroid_x)
and damping rate (log decrement of the first two maxima above the late mean, over their time
apart), the lattice start beside the mean ± standard deviation of the jittered realisations,
and the Richardson estimates of the period and damping from the three finest lattice points and
from nx = 30, 60, 120. The nx = 30 and
45 lattice runs are the rule's own (capillary-rule/runs). Prints a markdown table (stdlib only).
Usage: examples/analysis/period_convergence.py RUNDIR RULE_RUNDIR"""
import math, os, statistics, sys

sys.path.insert(0, os.path.dirname(__file__))
from capillary_rule import status  # noqa: E402
from pb_sweep import osc, series  # noqa: E402

NXS = [24, 30, 36, 45, 60, 120]
SEEDS = [1, 2, 3]


def damping(d):
    s = series(d)
    t = [r["t"] for r in s]
    raw = [r["centroid_x"] for r in s]
    x = [sum(raw[max(0, i - 2):i + 3]) / len(raw[max(0, i - 2):i + 3]) for i in range(len(raw))]
    late = statistics.mean(xi for ti, xi in zip(t, raw) if ti >= 0.4)
    peaks = [i for i in range(1, len(x) - 1) if x[i] >= x[i - 1] and x[i] > x[i + 1] and x[i] > late]
    if len(peaks) < 2:
        return math.nan
    a, b = peaks[0], peaks[1]
    return math.log((x[a] - late) / (x[b] - late)) / (t[b] - t[a])


def point(d):
    st, _ = status(d)
    if st != "ok":
        return None
    return {"period": osc(d)[0], "gamma": damping(d)}


def lattice_dir(runs, rule_runs, nx):
    own = f"{runs}/osc-nx{nx}-seed0"
    return own if os.path.exists(own + "/summary.json") else f"{rule_runs}/osc-nx{nx}-quintic-a2.0"


def fmt(v, prec=4):
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.{prec}f}"


def main():
    runs, rule_runs = sys.argv[1], sys.argv[2]
    print("| nx | R/Δx | period, lattice | period, jittered | damping γ, lattice | γ, jittered |")
    print("|---|---|---|---|---|---|")
    lat = {}
    for nx in NXS:
        p = point(lattice_dir(runs, rule_runs, nx))
        lat[nx] = p
        real = [q for q in (point(f"{runs}/osc-nx{nx}-seed{s}") for s in SEEDS) if q]
        cells = []
        for key in ["period", "gamma"]:
            vals = [q[key] for q in real if not math.isnan(q[key])]
            spread = "—"
            if vals:
                sd = statistics.stdev(vals) if len(vals) > 1 else math.nan
                spread = f"{fmt(statistics.mean(vals))} ± {fmt(sd)} (n = {len(vals)})"
            cells += [fmt(p[key] if p else None), spread]
        print(f"| {nx} | {0.1875 * nx / 0.5:.2f} | " + " | ".join(cells) + " |")
    fine = [nx for nx in NXS if lat.get(nx)][-3:]
    for pts in [fine, [30, 60, 120]]:
        if all(lat.get(nx) for nx in pts) and len(pts) == 3:
            for key in ["period", "gamma"]:
                richardson(pts, [lat[nx][key] for nx in pts], key)
        else:
            print(f"\nRichardson needs three lattice points of {pts}; have {[nx for nx in pts if lat.get(nx)]}")


def richardson(nxs, f, key):
    """f = f* + C h^p through three points (h = 1/nx, ratios need not be equal): p by bisection."""
    h = [1.0 / nx for nx in nxs]
    vals = ", ".join(f"{v:.4f}" for v in f)
    ratio = (f[1] - f[0]) / (f[2] - f[1]) if f[2] != f[1] else math.nan
    if not ratio > 0:
        print(f"\nRichardson on nx = {nxs}: {key} {vals} not monotone: no order")
        return
    g = lambda q: (h[1] ** q - h[0] ** q) / (h[2] ** q - h[1] ** q) - ratio
    lo, hi = 0.05, 8.0
    if g(lo) * g(hi) > 0:
        print(f"\nRichardson on nx = {nxs}: {key} {vals}: no order in [{lo}, {hi}] fits (ratio {ratio:.3f})")
        return
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(lo) * g(mid) > 0 else (lo, mid)
    q = 0.5 * (lo + hi)
    c = (f[2] - f[1]) / (h[2] ** q - h[1] ** q)
    print(f"\nRichardson on nx = {nxs}: {key} {vals}: observed order {q:.2f}, extrapolated {f[2] - c * h[2] ** q:.4f}")


if __name__ == "__main__":
    main()
