#!/usr/bin/env python3
"""Fits each shear-wave run's kinetic energy (README.md) with a Kelvin-Voigt medium: the square
wave's odd Fourier modes m = 1, 3, 5, ... (wavenumber mk, k = 2*pi/0.5, energy share 1/m^2), each
u'' + nu (mk)^2 u' + (G/rho)(mk)^2 u = 0 from u = 0, u' = 1. Grid search over G/rho and nu for
the least squares of sqrt(KE/KE0) over t <= T (default 0.6). Prints G/rho, G/(rho p_b), nu and
the fit's rms. With --svg FILE, plots KE/KE0 (log) against t for the runs, each with its fit,
and the fluid's curve (G = 0, nu = 0.05). numpy only. Usage: shear_fit.py RUN... [--t T] [--svg FILE]"""
import csv, json, math, sys
import numpy as np

K = 2 * math.pi / 0.5
MODES = [1, 3, 5, 7, 9]


def mode_v(t, w2, beta):
    """u'(t) of u'' + 2 beta u' + w2 u = 0, u(0) = 0, u'(0) = 1."""
    d = beta * beta - w2
    if d < -1e-12:
        wd = math.sqrt(-d)
        return np.exp(-beta * t) * (np.cos(wd * t) - beta / wd * np.sin(wd * t))
    if d > 1e-12:
        s = math.sqrt(d)
        r1, r2 = -beta + s, -beta - s
        return (r1 * np.exp(r1 * t) - r2 * np.exp(r2 * t)) / (r1 - r2)
    return np.exp(-beta * t) * (1 - beta * t)


def model(t, g, nu):
    tot = np.zeros_like(t)
    norm = 0.0
    for m in MODES:
        km = m * K
        tot += mode_v(t, g * km * km, nu * km * km / 2) ** 2 / m**2
        norm += 1 / m**2
    return tot / norm


def fit(run, t_max):
    rows = list(csv.DictReader(open(f"{run}/series.csv")))
    t = np.array([float(r["t"]) for r in rows])
    ke = np.array([float(r["kinetic_energy"]) for r in rows])
    sel = t <= t_max
    t, y = t[sel], np.sqrt(ke[sel] / ke[0])
    best = (math.inf, 0, 0)
    for g in np.concatenate([[0.0], np.geomspace(1e-3, 20, 400)]):
        for nu in np.linspace(0.02, 0.12, 101):
            e = float(np.sqrt(np.mean((np.sqrt(model(t, g, nu)) - y) ** 2)))
            if e < best[0]:
                best = (e, g, nu)
    pb = json.load(open(f"{run}/summary.json"))["parameters"]["phases"][0]["p_b"]
    return best, pb


def svg(path, curves, t_max):
    """curves: (label, colour, t, ke/ke0, fitted ke/ke0 or None)."""
    W, H, L, R, T, B = 760, 440, 70, 230, 40, 50
    lo, hi = -7.0, 0.0
    X = lambda t: L + (W - L - R) * t / t_max
    Y = lambda v: T + (H - T - B) * (hi - max(lo, math.log10(max(v, 1e-30)))) / (hi - lo)
    o = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
         f'<rect width="{W}" height="{H}" fill="white"/>',
         f'<text x="{L}" y="22" font-size="14">Square shear wave, doubly periodic, one fluid: kinetic energy</text>']
    for e in range(int(lo), int(hi) + 1):
        o.append(f'<line x1="{L}" x2="{W - R}" y1="{Y(10**e):.1f}" y2="{Y(10**e):.1f}" stroke="#ddd"/>')
        o.append(f'<text x="{L - 8}" y="{Y(10**e) + 4:.1f}" text-anchor="end">1e{e}</text>')
    for k in range(0, 7):
        t = k * t_max / 6
        o.append(f'<text x="{X(t):.1f}" y="{H - B + 18}" text-anchor="middle">{t:.1f}</text>')
    o.append(f'<rect x="{L}" y="{T}" width="{W - L - R}" height="{H - T - B}" fill="none" stroke="black"/>')
    o.append(f'<text x="{(L + W - R) / 2}" y="{H - 10}" text-anchor="middle">t</text>')
    o.append(f'<text x="16" y="{(T + H - B) / 2}" transform="rotate(-90 16 {(T + H - B) / 2})" text-anchor="middle">KE / KE(0)</text>')
    for n, (label, col, t, y, f) in enumerate(curves):
        pts = " ".join(f"{X(a):.1f},{Y(b):.1f}" for a, b in zip(t, y) if a <= t_max)
        o.append(f'<polyline points="{pts}" fill="none" stroke="{col}" stroke-width="2"/>')
        if f is not None:
            pts = " ".join(f"{X(a):.1f},{Y(b):.1f}" for a, b in zip(t, f) if a <= t_max)
            o.append(f'<polyline points="{pts}" fill="none" stroke="{col}" stroke-width="1" stroke-dasharray="5,3"/>')
        ly = T + 14 + 34 * n
        o.append(f'<line x1="{W - R + 12}" x2="{W - R + 36}" y1="{ly}" y2="{ly}" stroke="{col}" stroke-width="2"/>')
        for j, part in enumerate(label.split("\n")):
            o.append(f'<text x="{W - R + 42}" y="{ly + 4 + 13 * j}">{part}</text>')
    o.append(f'<text x="{W - R + 12}" y="{H - B - 4}" font-size="11">dashed: Kelvin-Voigt fit</text>')
    o.append("</svg>")
    open(path, "w").write("\n".join(o) + "\n")


COLOURS = ["#d62728", "#ff7f0e", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b"]

if __name__ == "__main__":
    args = sys.argv[1:]
    t_max = 0.6
    out_svg = None
    if "--t" in args:
        i = args.index("--t")
        t_max = float(args[i + 1])
        del args[i : i + 2]
    if "--svg" in args:
        i = args.index("--svg")
        out_svg = args[i + 1]
        del args[i : i + 2]
    curves = []
    print("| run | p_b | G/ρ | G/(ρ p_b) | ν fitted | rms of √(KE/KE0) |")
    print("|---|---|---|---|---|---|")
    for run in args:
        (e, g, nu), pb = fit(run.rstrip("/"), t_max)
        name = run.rstrip("/").split("/")[-1]
        print(f"| {name} | {pb:.1f} | {g:.3f} | {g / pb:.4f} | {nu:.3f} | {e:.4f} |" if pb else f"| {name} | 0 | {g:.3f} | — | {nu:.3f} | {e:.4f} |")
        rows = list(csv.DictReader(open(f"{run.rstrip('/')}/series.csv")))
        t = np.array([float(r["t"]) for r in rows])
        ke = np.array([float(r["kinetic_energy"]) for r in rows])
        curves.append((f"{name}\np_b {pb:.1f}, G/ρ {g:.3f}", COLOURS[len(curves) % len(COLOURS)], t, ke / ke[0], model(t, g, nu)))
    if out_svg:
        t = np.linspace(0, t_max, 301)
        curves.append(("a fluid (G = 0, ν = 0.05)", "#000000", t, model(t, 0.0, 0.05), None))
        svg(out_svg, curves, t_max)
