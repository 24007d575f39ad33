#!/usr/bin/env python3
"""Speed against physical error: time to solution against the error of the
oscillating drop's period (thesis 0.37) and of relax-60's equilibrium angle (60°), across
kernels × p_b × resolution × precision, with the Pareto front (no other run both faster and
more accurate). Reads the runs of examples/analysis/speed_vs_physical_error.sh, the p_b sweep's nx = 24 drop
runs and relax-60's long runs; writes OUT/speed_vs_physical_error.csv, OUT/*.svg (log-log) and
OUT/summary.md (stdlib only). Usage: examples/analysis/speed_vs_physical_error.py RUNDIR OUTDIR"""
import csv, glob, json, math, os, sys

sys.path.insert(0, os.path.dirname(__file__))
from pb_sweep import osc  # noqa: E402  (the sweep's period estimator, same set-up)

THESIS_PERIOD, TARGET_ANGLE = 0.37, 60.0
# Resolution floors: an error below them is not told apart from zero, so it is drawn on the
# floor and ties there on the Pareto front. drop: the thesis quotes T = 0.37 to two digits
# (±0.005, coarser than the 0.002 series sampling of the period estimator); relax-60: one
# 0.2-wide window of one run scatters by up to 2.96° (reports/validation/relax-60/nx45, dt check).
FLOOR = {"drop": max(0.005, 0.002) / THESIS_PERIOD, "relax-60": 2.96 / TARGET_ANGLE}
FLOOR_WHY = {"drop": "thesis T = 0.37 ± 0.005", "relax-60": "one run's window scatter, 2.96°"}


def summary(d):
    p = d + "/summary.json"
    return json.load(open(p)) if os.path.exists(p) else None


KAPPA = {"quintic": 3.0, "cubic-spline": 2.0, "wendland-c2": 2.0, "gaussian": 3.0}


def pair_work(s):
    """Deterministic cost: pair interactions evaluated, 2 evaluations per midpoint step (relaxation
    included) × particles (fluid + wall) × π(κh/Δx)² neighbours each, in units of 1e9."""
    par = s["parameters"]
    nx, k = par["domain"]["nx"], par["kernel"]
    n = sum(c for _, c in s.get("particles_per_phase", [])) + s.get("wall_particles", 0)
    evals = 2 if par["time"]["integrator"] == "midpoint" else 1
    steps = (s.get("steps") or 0) + (s.get("relax_steps") or 0)
    return steps * evals * n * math.pi * (KAPPA.get(k["kind"], 3.0) * k["h_ratio"]) ** 2 / 1e9


def point(d, s):
    par = s["parameters"]
    return {
        "run": os.path.relpath(d),
        "kernel": f'{par["kernel"]["kind"]} h={par["kernel"]["h_ratio"]}Δx'
        + (" (transport)" if par["time"].get("background") == "transport" else ""),
        "nx": par["domain"]["nx"],
        "p_b": par["phases"][0]["p_b"],
        "p_b_dx_over_sigma": par["phases"][0]["p_b"] * 0.5 / par["domain"]["nx"],
        "precision": s.get("precision", "f64"),
        "backend": s.get("backend", "cpu1"),
        "gpu": "." in s.get("backend", "") and not s.get("backend", "").startswith("cpu"),
        "steps": s.get("steps"),
        "wall_time_s": s.get("wall_time_s", math.nan),
        "ms_per_step": s.get("ms_per_step", math.nan),
        "commit": s.get("git_commit") or s.get("provenance", {}).get("commit", "?"),
        "date": s.get("provenance", {}).get("date", "?"),
        "adapter": device(s),
        "pair_work_1e9": pair_work(s),
        "status": s.get("status", "?"),
    }


def device(s):
    """Where the run ran: the GPU adapter and driver from the provenance, or the host CPU."""
    prov = s.get("provenance", {})
    g = prov.get("gpu")
    if g:
        return f'{g.get("adapter", "?")} / {g.get("driver", "?")}'
    host = prov.get("host", {})  # host.threads is the rayon pool; the cpu1 backend runs on one thread
    threads = 1 if s.get("backend", "").startswith("cpu1") else host.get("threads", "?")
    return f'{host.get("cpu", "CPU")} ({threads} thread{"" if threads == 1 else "s"})'


def drop_points(dirs):
    pts = []
    for d in dirs:
        s = summary(d)
        if not s or s.get("status") != "ok":
            continue
        p = point(d, s)
        p["case"] = "drop"
        if p["status"] == "ok":
            period, amp, late, nmax = osc(d)
            p.update(quantity=period, error=abs(period / THESIS_PERIOD - 1.0))
        else:
            p.update(quantity=math.nan, error=math.nan)
        pts.append(p)
    return pts


def relax_points(dirs):
    pts = []
    for d in dirs:
        s = summary(d)
        if not s or s.get("status") != "ok" or s["options"].get("t_end") != 5.0:
            continue
        p = point(d, s)
        p["case"] = "relax-60"
        rows = [r for r in csv.DictReader(open(d + "/series.csv"))]
        th = [float(r["theta_circle_fit"]) for r in rows if r["theta_circle_fit"] and 4.3 <= float(r["t"]) <= 4.5]
        if p["status"] == "ok" and th:
            m = sum(th) / len(th)
            p.update(quantity=m, error=abs(m - TARGET_ANGLE) / TARGET_ANGLE)
        else:
            p.update(quantity=math.nan, error=math.nan)
        pts.append(p)
    return pts


def centroid(run):
    return [(float(r["t"]), float(r["centroid_x"])) for r in csv.DictReader(open(run + "/series.csv"))]


def gpu_section(drop):
    """Each GPU drop run beside the CPU f64 run of the same kernel, nx and p_b: the largest
    difference of the centroid curve over the whole run, against the first-cycle amplitude."""
    md = ["## GPU variants against the CPU reference (drop)", "",
          "Each GPU run beside the one-thread CPU f64 run of the same scene (kernel, nx, p_b): the largest "
          "|Δ centroid_x| over every series row (t = 0 to 0.6, same sample times), the period each gives, "
          "and the wall-time ratio (lavapipe on the same 2 cores: a ratio between two CPU programs, not a GPU figure).", "",
          "| GPU variant | nx | CPU run | max abs. Δ centroid_x | period GPU / CPU | wall time GPU / CPU |",
          "|---|---|---|---|---|---|"]
    cpu = [p for p in drop if not p["gpu"] and p["precision"] == "f64"]
    for g in sorted((p for p in drop if p["gpu"]), key=lambda p: (p["nx"], p["backend"])):
        ref = [c for c in cpu if (c["kernel"], c["nx"], c["p_b"]) == (g["kernel"], g["nx"], g["p_b"])]
        if not ref:
            md.append(f'| {g["backend"]} | {g["nx"]} | none of the same set-up | — | {g["quantity"]:.4g} / — | — |')
            continue
        c = ref[0]
        a, b = centroid(g["run"]), centroid(c["run"])
        same = len(a) == len(b) and all(abs(x[0] - y[0]) < 1e-9 for x, y in zip(a, b))
        dmax = max(abs(x[1] - y[1]) for x, y in zip(a, b)) if same else math.nan
        md.append(f'| {g["backend"]} | {g["nx"]} | {c["run"].split("/")[-1]} ({c["backend"]}) | '
                  f'{dmax:.2e} | {g["quantity"]:.4g} / {c["quantity"]:.4g} | {g["wall_time_s"] / c["wall_time_s"]:.2f} |')
    return md + [""]


def floored(p):
    """The error as the plot and the front read it: at least the case's resolution floor."""
    return max(p["error"], FLOOR[p["case"]])


def pareto(pts, x, flag):
    ok = [p for p in pts if math.isfinite(p["error"]) and math.isfinite(p[x])]
    for p in pts:
        p["error_floor"] = FLOOR[p["case"]]
        p["below_floor"] = math.isfinite(p["error"]) and p["error"] < p["error_floor"]
        p[flag] = p in ok and not any(
            q is not p and q[x] <= p[x] and floored(q) <= floored(p)
            and (q[x] < p[x] or floored(q) < floored(p)) for q in ok)


COLOURS = {"quintic": "#1f77b4", "cubic-spline": "#d62728", "wendland-c2": "#2ca02c", "gaussian": "#9467bd",
           "johnson": "#ff7f0e"}


def where(pts):
    """The machines the points ran on, for the plot's subtitle."""
    cpus = sorted({p["adapter"].split(" (")[0] for p in pts if not p["gpu"]})
    if "CPU" in cpus and len(cpus) > 1:  # older summaries name no host
        cpus = [c for c in cpus if c != "CPU"] + ["older runs' host not recorded"]
    gpus = sorted({p["adapter"].split(" / ")[0] for p in pts if p["gpu"]})
    text = "CPU: " + ", ".join(cpus)
    if gpus:
        text += "; GPU rows: " + ", ".join(gpus)
        if any("llvmpipe" in g for g in gpus):
            text += " (a CPU emulation of Vulkan: ratios only)"
    return text


def svg(pts, path, title, ylabel, x="wall_time_s", flag="pareto", xlabel="time to solution: wall time (s), one thread, shared 2-core machine (log)"):
    ok = [p for p in pts if math.isfinite(p["error"]) and p[x] > 0]
    if not ok:
        return
    floor = FLOOR[ok[0]["case"]]
    W, H, L, R, T, B = 860, 560, 80, 300, 66, 60
    lx = [math.log10(p[x]) for p in ok]
    ly = [math.log10(floored(p)) for p in ok]
    x0, x1 = math.floor(min(lx)), math.ceil(max(lx))
    y0, y1 = math.floor(math.log10(floor)) - 1, max(math.ceil(max(ly)), math.floor(math.log10(floor)) + 1)
    Xv = lambda v: L + (math.log10(v) - x0) / (x1 - x0) * (W - L - R)
    Y = lambda v: H - B - (math.log10(v) - y0) / (y1 - y0) * (H - T - B)
    o = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="11">',
         f'<rect width="{W}" height="{H}" fill="white"/>',
         f'<text x="{(L + W - R) / 2}" y="20" text-anchor="middle" font-size="14">{title}</text>',
         *(f'<text x="{(L + W - R) / 2}" y="{34 + 12 * i}" text-anchor="middle" font-size="10" fill="#444">{line}</text>'
           for i, line in enumerate(where(ok).split("; "))),
         f'<rect x="{L}" y="{Y(floor):.1f}" width="{W - L - R}" height="{H - B - Y(floor):.1f}" fill="#eee"/>',
         f'<line x1="{L}" y1="{Y(floor):.1f}" x2="{W - R}" y2="{Y(floor):.1f}" stroke="#888" stroke-dasharray="2,2"/>',
         f'<text x="{W - R - 6}" y="{H - B - 22}" text-anchor="end" font-size="10" fill="#444">'
         f'below the dotted line: under the resolution floor {floor:.3g}</text>',
         f'<text x="{W - R - 6}" y="{H - B - 8}" text-anchor="end" font-size="10" fill="#444">'
         f'({FLOOR_WHY[ok[0]["case"]]}); such points are drawn on it, ▾</text>',
         f'<rect x="{L}" y="{T}" width="{W - L - R}" height="{H - T - B}" fill="none" stroke="black"/>']
    for e in range(x0, x1 + 1):
        for m in range(1, 10):
            v = m * 10 ** e
            if e == x1 and m > 1:
                break
            xp = Xv(v)
            o.append(f'<line x1="{xp:.1f}" y1="{H - B}" x2="{xp:.1f}" y2="{H - B + (6 if m == 1 else 3)}" stroke="black"/>')
            if m == 1:
                o.append(f'<line x1="{xp:.1f}" y1="{T}" x2="{xp:.1f}" y2="{H - B}" stroke="#ddd"/>')
                o.append(f'<text x="{xp:.1f}" y="{H - B + 18}" text-anchor="middle">{v:g}</text>')
    for e in range(y0, y1 + 1):
        y = Y(10 ** e)
        o.append(f'<line x1="{L - 6}" y1="{y:.1f}" x2="{L}" y2="{y:.1f}" stroke="black"/>')
        o.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="#ddd"/>')
        o.append(f'<text x="{L - 8}" y="{y + 4:.1f}" text-anchor="end">{10 ** e:g}</text>')
    o.append(f'<text x="{(L + W - R) / 2}" y="{H - 15}" text-anchor="middle">{xlabel}</text>')
    o.append(f'<text transform="translate(18,{(T + H - B) / 2}) rotate(-90)" text-anchor="middle">{ylabel} (log)</text>')
    front = sorted([p for p in ok if p[flag]], key=lambda p: p[x])
    if len(front) > 1:
        o.append('<polyline fill="none" stroke="black" stroke-dasharray="4,3" points="' +
                 " ".join(f'{Xv(p[x]):.1f},{Y(floored(p)):.1f}' for p in front) + '"/>')
    for p in ok:
        kind = p["kernel"].split()[0]
        xp, y, c = Xv(p[x]), Y(floored(p)), COLOURS.get(kind, "black")
        r = 3 + 1.5 * (p["nx"] - 20) / 10
        if p["gpu"]:  # a GPU variant: a triangle (filled f64, open f32)
            pts_ = f"{xp:.1f},{y - r - 1:.1f} {xp - r - 1:.1f},{y + r:.1f} {xp + r + 1:.1f},{y + r:.1f}"
            fill = "none" if p["precision"] == "f32" else c
            o.append(f'<polygon points="{pts_}" fill="{fill}" fill-opacity="0.5" stroke="{c}" stroke-width="1.5"/>')
        elif p["precision"] == "f32":
            o.append(f'<rect x="{xp - r:.1f}" y="{y - r:.1f}" width="{2 * r:.1f}" height="{2 * r:.1f}" fill="none" stroke="{c}" stroke-width="1.5"/>')
        else:
            o.append(f'<circle cx="{xp:.1f}" cy="{y:.1f}" r="{r:.1f}" fill="{c}" fill-opacity="0.5" stroke="{c}"/>')
        if p["below_floor"]:
            o.append(f'<text x="{xp:.1f}" y="{y + r + 10:.1f}" text-anchor="middle" font-size="10" fill="{c}">▾</text>')
    # The front's points are numbered on the plot and named in the legend column, so no label overprints.
    lx0, ly0 = W - R + 16, T + 6
    for i, p in enumerate(front, 1):
        xp, y = Xv(p[x]), Y(floored(p))
        r = 3 + 1.5 * (p["nx"] - 20) / 10
        o.append(f'<circle cx="{xp:.1f}" cy="{y:.1f}" r="{r + 4:.1f}" fill="none" stroke="black"/>')
        ty = y - r - 2 if i % 2 else y + r + 10  # alternate above and below, so close neighbours stay apart
        o.append(f'<text x="{xp + r + 5:.1f}" y="{ty:.1f}" font-size="10" font-weight="bold">{i}</text>')
    kinds = {p["kernel"].split()[0] for p in ok}
    for i, (k, c) in enumerate((k, c) for k, c in COLOURS.items() if k in kinds):
        o.append(f'<circle cx="{lx0 + 4}" cy="{ly0 + 16 * i}" r="5" fill="{c}" fill-opacity="0.5" stroke="{c}"/>')
        o.append(f'<text x="{lx0 + 14}" y="{ly0 + 16 * i + 4}">{k}</text>')
    yy = ly0 + 16 * len(kinds & COLOURS.keys())
    o.append(f'<circle cx="{lx0 + 4}" cy="{yy}" r="5" fill="gray"/><text x="{lx0 + 14}" y="{yy + 4}">CPU f64 (size: nx)</text>')
    o.append(f'<rect x="{lx0 - 1}" y="{yy + 11}" width="10" height="10" fill="none" stroke="gray"/><text x="{lx0 + 14}" y="{yy + 20}">CPU f32</text>')
    o.append(f'<polygon points="{lx0 + 4},{yy + 26} {lx0 - 2},{yy + 37} {lx0 + 10},{yy + 37}" fill="none" stroke="gray"/>'
             f'<text x="{lx0 + 14}" y="{yy + 36}">GPU variant (open f32, filled f64)</text>')
    o.append(f'<circle cx="{lx0 + 4}" cy="{yy + 50}" r="8" fill="none" stroke="black"/><text x="{lx0 + 16}" y="{yy + 54}">Pareto front (dashed), numbered:</text>')
    for i, p in enumerate(front, 1):
        k = p["kernel"].split()
        name = f'{k[0]} {k[1].replace("h=", "h ")}, nx {p["nx"]}, p_b {p["p_b"]:g}, {p["precision"]}'
        o.append(f'<text x="{lx0}" y="{yy + 60 + 26 * i}" font-size="10">{i}. {name}</text>')
        o.append(f'<text x="{lx0 + 12}" y="{yy + 72 + 26 * i}" font-size="10" fill="#444">{p["backend"] if p["gpu"] else "CPU " + p["backend"]}</text>')
    o.append("</svg>")
    open(path, "w").write("\n".join(o))


def main():
    runs, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    drops = sorted(glob.glob(f"{runs}/drop-*/")) + sorted(glob.glob("reports/validation/pb-sweep/runs/*-osc/"))
    relaxes = (sorted(glob.glob(f"{runs}/relax-*/")) + sorted(glob.glob("reports/validation/relax-60/runs/b-noslip*/"))
               + sorted(glob.glob("reports/validation/relax-60/nx45/runs/b-noslip*/"))
               + sorted(glob.glob("reports/validation/convergence/runs/nx*/"))
               + sorted(glob.glob("reports/validation/convergence/pb-check/runs/nx*/")))
    # Only the 90° start: relax-60's runs from a 45° cap (`*-from45`) relax from the other side
    # and take another time to solution.
    relaxes = [d for d in relaxes if "-from" not in d]
    drop, relax = drop_points([d.rstrip("/") for d in drops]), relax_points([d.rstrip("/") for d in relaxes])
    for pts in (drop, relax):
        pareto(pts, "pair_work_1e9", "pareto")
        pareto(pts, "wall_time_s", "pareto_wall")
    keys = ["case", "backend", "kernel", "nx", "p_b", "p_b_dx_over_sigma", "precision", "steps", "pair_work_1e9", "wall_time_s",
            "ms_per_step", "quantity", "error", "error_floor", "below_floor", "pareto", "pareto_wall", "status", "adapter", "commit", "date", "run"]
    with open(f"{out}/speed_vs_physical_error.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for p in drop + relax:
            w.writerow(p)
    wl = "pair interactions evaluated (1e9; steps × 2 evaluations × particles × π(κh/Δx)²) (log)"
    svg(drop, f"{out}/drop_work_vs_period_error.svg", "Oscillating drop: work to solution vs period error",
        "|T − 0.37| / 0.37", "pair_work_1e9", "pareto", wl)
    svg(relax, f"{out}/relax60_work_vs_angle_error.svg", "relax-60 Mode B no-slip: work to solution vs angle error",
        "|θ(t ≈ 4.4) − 60°| / 60°", "pair_work_1e9", "pareto", wl)
    svg(drop, f"{out}/drop_time_vs_period_error.svg", "Oscillating drop: wall time vs period error (load-dependent)",
        "|T − 0.37| / 0.37", "wall_time_s", "pareto_wall")
    svg(relax, f"{out}/relax60_time_vs_angle_error.svg", "relax-60 Mode B no-slip: wall time vs angle error (load-dependent)",
        "|θ(t ≈ 4.4) − 60°| / 60°", "wall_time_s", "pareto_wall")
    md = ["# Speed against physical error", "",
          "CPU runs, one thread each, and GPU variants on lavapipe (Mesa's software Vulkan on the same CPU: a GPU row's "
          "wall time is a CPU's, kept to compare variants, precisions and resolutions with each other, not with hardware), "
          "on the shared 2-core machine (`examples/analysis/speed_vs_physical_error.sh`, analysed by "
          "`examples/analysis/speed_vs_physical_error.py`). Time to solution = the run's wall time (`summary.json`). It carries "
          "the machine's load at the time (five other sessions compiling and running): the same run's ms/step varied "
          "about 5× between runs here, so the Pareto front is drawn on a deterministic work measure instead — pair "
          "interactions evaluated, steps (relaxation included) × 2 evaluations × (fluid + wall particles) × π(κh/Δx)² — "
          "which counts kernel support and resolution but not precision (f32 and f64 points share their work; their "
          "wall times are in the table). The wall-time plots are kept for completeness.", "",
          "* **drop**: the oscillating drop, relax 0.1, the T84 field on every fluid particle, t = 0.6; error = "
          "|T − 0.37|/0.37 (thesis period; period = time between the first two centroid maxima of a 5-sample "
          "moving average, the p_b sweep's estimator). nx = 24 f64 runs are the p_b sweep's (Wendland h = 1.3Δx, "
          "commit 7fe2a4c); the others use Wendland h = 1.5Δx.",
          "* **relax-60**: Mode B no-slip to t = 5: the long runs of reports/validation/relax-60 (nx = 65 and, "
          "in relax-60/nx45, 45), convergence (dt scaled; p_b = max(11.25σ/R, 0.2314σ/Δx)) and its pb-check "
          "(the former rule σ/(2Δx) at nx = 65, 85, 105, and p_b = 30 at 65), and the committed nx = 33 run of commit 25041d7 (`runs/relax-nx33-pb33-f64`, copied "
          "from git); error = |θ − 60°|/60° with θ the circle-fit angle averaged over t ∈ [4.3, 4.5]. The kernel × p_b × "
          "precision runs at nx = 26 (`relax` in the script) were stopped for CPU time and are not in the table.",
          "* Pareto front: runs that no other run of the same case beats in both work and error (ringed and joined in "
          "the work plots, `pareto` in the CSV; `pareto_wall` is the same on wall time). Axes are log-log.",
          f"* Resolution floor: an error below it is not told apart from zero (drop: {FLOOR['drop']:.4f}, the thesis "
          f"quotes T = 0.37 to two digits, ±0.005, coarser than the estimator's 0.002 sampling; relax-60: {FLOOR['relax-60']:.4f}, "
          "one 0.2-wide window of one run scatters by up to 2.96°, relax-60/nx45's dt check). Such points are drawn on the "
          "floor (▾, `below_floor` in the CSV) and tie there on the front: the cheaper one is on it.", ""]
    for name, pts, q in [("drop", drop, "period"), ("relax-60", relax, "θ (deg)")]:
        md += [f"## {name}", "", f"| backend | kernel | nx | p_b (p_bΔx/σ) | precision | work (1e9 pairs) | wall time (s) | ms/step | {q} | rel. error | Pareto (work / wall) | adapter / driver | commit | date |",
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for p in sorted(pts, key=lambda p: p["pair_work_1e9"]):
            md.append(f'| {p["backend"]} | {p["kernel"]} | {p["nx"]} | {p["p_b"]:g} ({p["p_b_dx_over_sigma"]:.2f}) | {p["precision"]} | '
                      f'{p["pair_work_1e9"]:.2f} | {p["wall_time_s"]:.1f} | {p["ms_per_step"]:.2f} | {p["quantity"]:.4g} | '
                      f'{p["error"]:.4f} | {"**yes**" if p["pareto"] else "no"} / {"**yes**" if p["pareto_wall"] else "no"} | {p["adapter"]} | {p["commit"]} | {p["date"][:10]} |')
        md.append("")
    md += gpu_section(drop)
    md += ["## Plots and data", "", "* [drop_work_vs_period_error.svg](drop_work_vs_period_error.svg)",
           "* [relax60_work_vs_angle_error.svg](relax60_work_vs_angle_error.svg)",
           "* [drop_time_vs_period_error.svg](drop_time_vs_period_error.svg)",
           "* [relax60_time_vs_angle_error.svg](relax60_time_vs_angle_error.svg)",
           "* [speed_vs_physical_error.csv](speed_vs_physical_error.csv)", ""]
    open(f"{out}/summary.md", "w").write("\n".join(md))


if __name__ == "__main__":
    main()
