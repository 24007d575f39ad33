#!/usr/bin/env python3
"""Analysis of examples/analysis/pb_sweep.sh: one row per (kernel, p_b) with the drop
at rest's spurious speed, Laplace jump and void indicator and the oscillating drop's period,
amplitude and mean centroid. Writes OUT/pb_sweep.csv and OUT/summary.md (stdlib only).
Usage: examples/analysis/pb_sweep.py RUNDIR OUTDIR COMMIT"""
import csv, glob, json, math, os, sys

R, SIGMA, DX = 0.1875, 1.0, 1.0 / 48
LAPLACE = SIGMA / R                      # 2D Laplace jump σ/R
CENTROID = 4 * R / (3 * math.pi)         # quarter-circle centroid
SUPPORT = {"quintic": 3.0 * 1.0, "cubic-spline": 2.0 * 1.2, "wendland-c2": 2.0 * 1.3,
           "johnson": 2.0 * 1.2, "gaussian": 3.0 * 1.0}
CORE = ["quintic", "cubic-spline", "wendland-c2"]  # always listed; the others when they were run


def num(v):
    try:
        return float(v)
    except ValueError:  # empty or a text column (dt_limit)
        return math.nan


def series(d):
    return [{k: num(v) for k, v in r.items()} for r in csv.DictReader(open(d + "/series.csv"))]


def last_snapshot(d):
    f = sorted(glob.glob(d + "/particles_*.csv"))[-1]
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(f))]


def rest(d, kind):
    s = series(d)
    vmax = max(r["max_speed"] for r in s if r["t"] >= 0.1)
    parts = last_snapshot(d)
    sup = SUPPORT[kind] * DX
    pin = [p["p"] for p in parts if p["phase"] == 0 and math.hypot(p["x"], p["y"]) < R - sup]
    pout = [p["p"] for p in parts if p["phase"] == 1 and math.hypot(p["x"], p["y"]) > R + sup
            and p["x"] < 0.5 - sup and p["y"] < 0.5 - sup]
    jump = sum(pin) / len(pin) - sum(pout) / len(pout)
    rho = [p["rho"] for p in parts if p["phase"] in (0, 1)]
    return vmax, jump, min(rho), sum(1 for r in rho if r < 0.95)


def osc(d):
    """Period = time between the first two maxima of the 5-sample moving average of centroid_x
    (2 × first max → first min when no second maximum), amplitude = ½(first max − first min)."""
    s = [r for r in series(d) if r["t"] >= 0.0]
    t = [r["t"] for r in s]
    raw = [r["centroid_x"] for r in s]
    n = len(raw)
    x = [sum(raw[max(0, i - 2):i + 3]) / len(raw[max(0, i - 2):i + 3]) for i in range(n)]
    ext = [(i, +1) for i in range(1, n - 1) if x[i] >= x[i - 1] and x[i] > x[i + 1]]
    ext += [(i, -1) for i in range(1, n - 1) if x[i] <= x[i - 1] and x[i] < x[i + 1]]
    ext.sort()
    maxima = [i for i, k in ext if k > 0]
    if not maxima:
        return math.nan, math.nan, math.nan, 0
    m1 = maxima[0]
    minima = [i for i, k in ext if k < 0 and i > m1]
    later = [i for i in maxima if i > m1]
    if later:
        period = t[later[0]] - t[m1]
    elif minima:
        period = 2 * (t[minima[0]] - t[m1])
    else:
        period = math.nan
    amp = 0.5 * (x[m1] - x[minima[0]]) if minima else math.nan
    late = [xi for ti, xi in zip(t, raw) if ti >= 0.4]
    return period, amp, sum(late) / len(late), len(maxima)


def previous(out):
    """Rows of an earlier OUT/pb_sweep.csv by (background, kernel, p_b): particle snapshots are not
    committed (.gitignore), so a rest run without one keeps its earlier analysis."""
    path = out + "/pb_sweep.csv"
    if not os.path.exists(path):
        return {}
    return {(r.get("background", "momentum"), r["kernel"], int(float(r["p_b"]))): r for r in csv.DictReader(open(path))}


def main():
    runs, out, commit = sys.argv[1], sys.argv[2], sys.argv[3]
    os.makedirs(out, exist_ok=True)
    before = previous(out)
    rows = []
    sweeps = [("momentum", "", [0, 12, 24, 48, 175]), ("transport", "transport-", [48, 175, 1225])]
    for background, prefix, pbs in sweeps:
      for kind in SUPPORT:
        for pb in pbs:
            base = f"{runs}/{prefix}{kind}-pb{pb}"
            if (background != "momentum" or kind not in CORE) and not os.path.exists(base + "-rest"):
                continue
            row = {"background": background, "kernel": kind, "p_b": pb, "p_b_dx_over_sigma": pb * DX / SIGMA}
            for tag, fn, keys in [("rest", lambda d: rest(d, kind), ["spurious_speed", "laplace_jump", "min_rho", "n_rho_below_0.95"]),
                                  ("osc", osc, ["period", "amplitude", "late_centroid", "n_maxima"])]:
                d = f"{base}-{tag}"
                ok = os.path.exists(d + "/summary.json") and json.load(open(d + "/summary.json")).get("status") == "ok"
                old = before.get((background, kind, pb))
                if ok and tag == "rest" and not glob.glob(d + "/particles_*.csv") and old:
                    vals = [num(old[k]) for k in keys]  # snapshot not kept: the earlier analysis
                    vals[-1] = int(vals[-1])
                else:
                    vals = fn(d) if ok else [math.nan] * len(keys)
                row[tag + "_status"] = "ok" if ok else (json.load(open(d + "/summary.json")).get("status", "?")[:60]
                                                         if os.path.exists(d + "/summary.json") else "not run")
                row.update(dict(zip(keys, vals)))
            rows.append(row)
    keys = list(rows[0].keys())
    with open(out + "/pb_sweep.csv", "w", newline="") as f:
        w = csv.DictWriter(f, keys)
        w.writeheader()
        w.writerows(rows)
    md = [f"# Background-pressure sweep (commit {commit})", "",
          "Oscillating-drop scene at nx = 24 (Δx = 1/48, σ/Δx = 48, σ/R = 5.33), CPU f64, one thread "
          "(`examples/analysis/pb_sweep.sh`, analysed by `examples/analysis/pb_sweep.py`). *rest*: no initial velocity, no "
          "relaxation, t = 0.3: max fluid speed over t ≥ 0.1, Laplace jump (mean p of the liquid deeper "
          "than one support inside the circle minus the gas beyond one support outside it and away from "
          "the walls; 2D theory σ/R = 5.333), min ρ/ρ0 and the number of fluid particles with ρ < 0.95ρ0 "
          "at the end (voids). *osc*: relax 0.1, the T84 field on every fluid particle, t = 0.6: period "
          "= time between the first two maxima of centroid_x (5-sample moving average; 2 × first max → "
          "first min when the second maximum is damped away), amplitude ½(first max − first min) "
          "(thesis 0.37, 0.012), mean centroid over t ≥ 0.4 (circle 0.0796).", "",
          "*p_b acts in*: `momentum` = the EOS and the momentum equation (the thesis's form, the default); "
          "`transport` = the transport-velocity formulation (`time.background = \"transport\"`, Adami, Hu & "
          "Adams 2013: no p_b in the EOS, the advection velocity ṽ = v + (dt/2)a_b), where the Laplace jump "
          "is read from the EOS pressure without p_b.", "",
          "| p_b acts in | kernel | p_b | p_b Δx/σ | spurious speed | Laplace jump | jump error | min ρ/ρ0 | n(ρ<0.95) | period | amplitude | late centroid |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        je = (r["laplace_jump"] - LAPLACE) / LAPLACE * 100
        md.append(f"| {r['background']} | {r['kernel']} | {r['p_b']} | {r['p_b_dx_over_sigma']:.3f} | {r['spurious_speed']:.3f} | "
                  f"{r['laplace_jump']:.3f} | {je:+.1f} % | {r['min_rho']:.3f} | {r['n_rho_below_0.95']} | "
                  f"{r['period']:.3f} | {r['amplitude']:.4f} | {r['late_centroid']:.4f} |"
                  + ("" if r["rest_status"] == "ok" and r["osc_status"] == "ok"
                     else f" rest: {r['rest_status']}; osc: {r['osc_status']}"))
    md += ["", "## The rule", "",
           "The built-ins use **p_b = σ/(2Δx)** (p_b Δx/σ = 0.5; 24 on this sweep, 30 for the default "
           "oscillating drop, 65 for sessile-90 / relax-60). Reading the table: p_b is a trade between two "
           "errors. Too low (p_b Δx/σ ≤ 0.25) the pressure cannot carry the Hu–Adams band tension "
           "σ|∇C|/2 ≈ 0.23σ/Δx: spurious speeds of 0.27–0.99 and Laplace jumps 8–64 % low. Too high "
           "(p_b = B = 175, p_b Δx/σ = 3.6) the pressure-sum error on the disordered lattice acts as a "
           "spring: the cubic-spline and Wendland drops ring at T ≈ 0.19 and 0.14 with a third to a half "
           "of the amplitude, like an elastic solid. At p_b Δx/σ = 0.5 the quintic, the cubic spline and Wendland C2 oscillate like a liquid (period "
           "0.32–0.39 on this coarse lattice, centroid back on the circle's 0.0796) with spurious speeds "
           "≤ 0.13 and a Laplace jump within 4–6 % at nx = 24 (−2.0 % for the quintic at the default nx = 30, "
           "reports/validation/spurious); p_b Δx/σ = 1 improves the jump (within 2.1 %) and the spurious speed "
           "(≤ 0.084) but shortens the cubic-spline and Wendland periods to 0.28 and 0.27, 17–20 % below "
           "the quintic's 0.344. No voids were detected at any p_b "
           "(min ρ/ρ0 ≥ 0.987, no fluid particle below 0.95ρ0 at the end of the rest runs). Rows marked "
           "'not run', if any, did not finish.",
           "", "## The thesis's other two kernels", "",
           "The truncated Gaussian (T40, h = Δx, support 3Δx) behaves like the quintic: at the rule period 0.370 "
           "(quintic 0.390), amplitude 0.0085, Laplace jump −7.6 %, spurious speed 0.10; at p_b Δx/σ = 1 period "
           "0.328 and jump −3.3 %; at B = 175 it rings at 0.268 and its centroid settles at 0.0838 (solid-like, "
           "as the cubic spline). The Johnson quadratic (T41) at h = 1.2Δx (support 2.4Δx, docs/PHYSICS.md §1's "
           "lattice-sum value) is solid-like at every p_b > 0: periods 0.260, 0.222, 0.188 and 0.098 at p_b 12, "
           "24, 48 and 175, spurious speeds 0.02–0.06 and Laplace jumps 9–17 % low; only p_b = 0 gives a liquid's "
           "period (0.376), at a spurious speed of 0.82. Its gradient does not vanish as r → 0 (f'(0) ≠ 0, "
           "docs/PHYSICS.md §1), so the pressure term of close pairs is a stiff repulsion that holds the lattice. "
           "Widening the support removes it: at the rule, h = 1.5Δx (support 3Δx) gives period 0.334 and "
           "jump −6.0 %, and h = 2Δx gives 0.372 and −0.1 % (johnson-h/README.md). `validate oscillation` "
           "runs it at h = 2Δx (at nx = 30, h = 1.5Δx still rings 27 % fast; h = 2Δx is 8 % off the quintic).",
           "", "## The transport-velocity formulation", "",
           "With `time.background = \"transport\"` (Adami, Hu & Adams 2013; CPU only) p_b leaves the EOS and "
           "the momentum equation and only moves the particles (ṽ = v + (dt/2)a_b, a_b the pressure term of a "
           "uniform p_b). It needs a large p_b: at p_b = 48 and 175 the shift cannot hold the particles against "
           "the band tension (spurious speeds 0.77–0.95, Laplace jumps 18–49 % low). At **p_b = ρ0c0² = 1225** "
           "(Adami's and PySPH's choice) the three kernels behave alike, unlike the momentum form: periods "
           "0.394–0.412 (spread 4 %; momentum form at the rule 0.322–0.390, spread 19 %) and first-cycle amplitudes "
           "0.0103–0.0110 (thesis 0.012; momentum form 0.0084–0.0092), with Laplace jumps 2.9–5.3 % low, no voids, "
           "and spurious speeds 0.21–0.28 (2–3× the momentum form's at the rule). On `relax-60` Mode B no-slip it "
           "removes the contact-line pinning (`relax-nx25/`, nx = 25, t ∈ [1.5, 2.5]: circle-fit θ 59.5°, D/D0 "
           "1.381 at p_b = 400 = ρ0c0², against 60.7°, 1.371 for the momentum form at p_b = 25; p_b 25 and 100 "
           "in the transport form over-spread to D/D0 1.72 and 1.48); at nx = 45 to t = 5 see "
           "../relax-60/summary.md (`b-noslip-tvf`). The built-ins keep the momentum form: it is the thesis's, "
           "every GPU variant runs it, and its spurious currents are smaller."]
    open(out + "/summary.md", "w").write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
