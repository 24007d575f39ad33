//! `sphlab forces RUN_DIR`: the force balance ([`super::balance`]) of one saved state of a
//! run, or its mean over the run's last K states, in a window around the right contact point, as
//! Markdown (and per particle as CSV). The scene comes from the run's `summary.json`, the states
//! from its `particles_<step>.csv` files.

use super::balance::{
    band_tension, cut_rows, evaluate_state, split_forces, total, Split, State, Window, PARTNER_NAMES, TERMS, TERM_NAMES,
};
use crate::cpu::momentum::PairTerm;
use crate::diagnostics::contact_half_width;
use crate::exec::Exec;
use crate::scene::{ContactMode, Scene};
use crate::validate::data::{read_series, read_snapshot, snapshot_files};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What to evaluate and where to sum.
#[derive(Clone, Debug)]
pub struct ForceOptions {
    /// Step of the snapshot (default: the last one).
    pub step: Option<u64>,
    /// x of the window's centre (default: the right contact point, [`contact_half_width`]).
    pub at: Option<f64>,
    /// Half-width of the window in Δx.
    pub half_width_dx: f64,
    /// Height of the window above the wall in Δx.
    pub height_dx: f64,
    /// x of the vertical cuts whose wall-band tensions are measured (each on the liquid side
    /// of the contact point or on its gas side by where it lies); when absent,
    /// `cuts_per_side` cuts evenly spaced on either side.
    pub cuts: Option<Vec<f64>>,
    /// Cuts per side when `cuts` is absent: at x0 + k(x_c − x0)/(n + 1) and
    /// x_c + k(x1 − x_c)/(n + 1), k = 1..n (1: half-way from x = domain.x[0] to the contact
    /// point and half-way from there to domain.x[1]).
    pub cuts_per_side: usize,
    /// Number of snapshots, ending at `step` (or the last), whose balances are averaged.
    pub last: usize,
    /// Per-particle CSV (every fluid particle, all 18 components).
    pub csv: Option<PathBuf>,
    /// Evaluation on all cores or one.
    pub exec: Exec,
}

/// The scene a run ran (`summary.json`'s `parameters`), validated.
pub fn run_scene(dir: &Path) -> Result<Scene, String> {
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("{}: {e} (RUN_DIR must be a `sphlab run` output)", path.display()))?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let p = v.get("parameters").ok_or_else(|| format!("{}: no `parameters` (the run's scene)", path.display()))?;
    let scene: Scene = serde_json::from_value(p.clone()).map_err(|e| format!("{}: parameters: {e}", path.display()))?;
    scene.validate().map_err(|e| format!("{}: parameters: {e}", path.display()))?;
    Ok(scene)
}

/// What one saved state gives: its window sums and its wall-band tensions.
struct StateBalance {
    step: u64,
    t: f64,
    x_c: f64,
    window: Window,
    cuts: Vec<f64>,
    /// Per cut: the tension of every term, then of each of [`TERMS`].
    tension: Vec<[Option<f64>; 4]>,
    /// Per cut: liquid and gas particles in the first three rows within Δx of it.
    above: Vec<[usize; 2]>,
}

/// The report of `dir`'s snapshot, or the mean over its last `o.last` snapshots (Markdown);
/// writes the CSV of the last state when asked.
pub fn force_report(dir: &Path, o: &ForceOptions) -> Result<String, String> {
    if !(o.half_width_dx > 0.0 && o.half_width_dx.is_finite() && o.height_dx > 0.0 && o.height_dx.is_finite()) {
        return Err(format!(
            "--half-width {} / --height {}: both must be positive numbers of Δx",
            o.half_width_dx, o.height_dx
        ));
    }
    if o.cuts.as_ref().is_some_and(|c| c.is_empty() || c.iter().any(|x| !x.is_finite())) || o.cuts_per_side == 0 {
        return Err(format!(
            "--cuts {:?} / --cuts-per-side {}: give at least one finite x, or at least one cut per side",
            o.cuts.as_deref().unwrap_or(&[]),
            o.cuts_per_side
        ));
    }
    let scene = run_scene(dir)?;
    let files = snapshot_files(dir);
    let end = match o.step {
        None => files.len().checked_sub(1).ok_or_else(|| format!("{}: no particles_*.csv snapshot", dir.display()))?,
        Some(s) => files.iter().position(|f| f.0 == s).ok_or_else(|| {
            let have: Vec<String> = files.iter().map(|f| f.0.to_string()).collect();
            format!("--step {s}: no such snapshot in {} (have: {})", dir.display(), have.join(", "))
        })?,
    };
    if o.last == 0 || o.last > end + 1 {
        return Err(format!(
            "--last {}: must be from 1 to the {} snapshots up to step {} in {}",
            o.last,
            end + 1,
            files[end].0,
            dir.display()
        ));
    }
    let series = read_series(dir);
    let mut states = Vec::new();
    for (k, (step, path)) in files[end + 1 - o.last..=end].iter().enumerate() {
        let csv = if k + 1 == o.last { o.csv.as_deref() } else { None };
        let t = series.iter().find(|r| r.step == *step).map_or(f64::NAN, |r| r.t);
        states.push(state_balance(&scene, *step, t, path, o, csv)?);
    }
    let k = states.len() as f64;
    let x_c = states.iter().map(|s| s.x_c).sum::<f64>() / k;
    let windows: Vec<Window> = states.iter().map(|s| s.window.clone()).collect();
    let mut md = markdown(dir, &scene, &states, x_c, o, &Window::mean(&windows));
    md.push_str(&cut_section(&scene, &states, x_c));
    Ok(md)
}

/// One state's balance.
fn state_balance(
    scene: &Scene,
    step: u64,
    t: f64,
    path: &Path,
    o: &ForceOptions,
    csv: Option<&Path>,
) -> Result<StateBalance, String> {
    let snap = read_snapshot(path, step, t).ok_or_else(|| format!("{}: not a readable snapshot", path.display()))?;
    let solver = evaluate_state(scene, &State { pos: &snap.pos, vel: &snap.vel, phase: &snap.phase }, o.exec)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let split = split_forces(&solver);
    let dx = scene.domain.dx();
    let y_w = solver.model.y_wall;
    let x_c = match o.at {
        Some(x) => x,
        None => contact_half_width(&snap.pos, &snap.phase, dx, y_w).ok_or_else(|| {
            format!("{}: no liquid particle in the first row: give the window's centre with --at X", path.display())
        })?,
    };
    let window = Window::sum(&snap.pos, &snap.phase, &split, x_c, o.half_width_dx * dx, y_w, o.height_dx * dx, dx);
    if let Some(csv) = csv {
        write_csv(csv, &snap.pos, &snap.phase, &split)?;
    }
    let [x0, x1] = scene.domain.x;
    let cuts = o.cuts.clone().unwrap_or_else(|| {
        let n = o.cuts_per_side;
        let at = |a: f64, b: f64, k: usize| a + (b - a) * k as f64 / (n + 1) as f64;
        (1..=n).map(|k| at(x0, x_c, k)).chain((1..=n).map(|k| at(x_c, x1, k))).collect()
    });
    let mut tension = Vec::with_capacity(cuts.len());
    let mut above = Vec::with_capacity(cuts.len());
    for &x in &cuts {
        let rows = cut_rows(&solver, x, dx, y_w);
        let of = |terms: &[PairTerm]| band_tension(&rows, terms, BAND_ROWS, BULK_ROWS);
        tension.push([of(&TERMS), of(&TERMS[0..1]), of(&TERMS[1..2]), of(&TERMS[2..3])]);
        let mut n = [0usize; 2];
        for i in 0..solver.n_fluid {
            let p = solver.pos[i];
            if (p.x - x).abs() < dx && p.y - y_w < 3.0 * dx && solver.phase[i] < 2 {
                n[solver.phase[i] as usize] += 1;
            }
        }
        above.push(n);
    }
    Ok(StateBalance { step, t, x_c, window, cuts, tension, above })
}

/// Rows of the wall band and of the uniform fluid above it, for [`band_tension`].
const BAND_ROWS: std::ops::Range<u32> = 0..4;
const BULK_ROWS: std::ops::Range<u32> = 5..9;

/// The wall-band tensions across the cuts (means over the states), by term; with several cuts
/// on a side, their mean and range; against Young's line force.
fn cut_section(scene: &Scene, states: &[StateBalance], x_c: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\n## Wall-band tension across vertical cuts\n\nAt each cut, the x-force on the fluid right of it from every particle left of it (fluid and wall), row by row; the band's tension is the deficit of rows {}–{} below the mean of rows {}–{} (uniform fluid), as `forces::balance::band_tension`. `--last K` averages K snapshots.\n",
        BAND_ROWS.start,
        BAND_ROWS.end - 1,
        BULK_ROWS.start,
        BULK_ROWS.end - 1
    );
    let _ = writeln!(out, "| cut | x | fluid above the wall there (last state) | tension | pressure part | viscous part | surface part |\n|---|---|---|---|---|---|---|");
    let k = states.len() as f64;
    let n_cuts = states.first().map_or(0, |s| s.cuts.len());
    // Per side (liquid, gas): each cut's mean tension of every term and of each term.
    let mut sides: [Vec<[f64; 4]>; 2] = [Vec::new(), Vec::new()];
    for c in 0..n_cuts {
        let x = states.iter().map(|s| s.cuts[c]).sum::<f64>() / k;
        let side = usize::from(x > x_c);
        let mean = |j: usize| -> Option<f64> {
            let v: Option<Vec<f64>> = states.iter().map(|s| s.tension[c][j]).collect();
            v.map(|v| v.iter().sum::<f64>() / k)
        };
        let m: [Option<f64>; 4] = std::array::from_fn(mean);
        let fmt = |v: Option<f64>| v.map_or("— (rows missing)".to_string(), |v| format!("{v:+.4}"));
        if let [Some(a), Some(p), Some(v), Some(st)] = m {
            sides[side].push([a, p, v, st]);
        }
        let last = states.last().map_or([0; 2], |s| s.above[c]);
        let _ = writeln!(
            out,
            "| {} | {x:.5} | {} liquid, {} gas | {} | {} | {} | {} |",
            ["liquid side", "gas side"][side],
            last[0],
            last[1],
            fmt(m[0]),
            fmt(m[1]),
            fmt(m[2]),
            fmt(m[3])
        );
    }
    let side_mean = |v: &[[f64; 4]], j: usize| v.iter().map(|t| t[j]).sum::<f64>() / v.len() as f64;
    let profile = sides.iter().any(|v| v.len() > 1);
    if profile {
        let _ = writeln!(out, "\n| side | cuts | tension, mean (range) | pressure part | viscous part | surface part |\n|---|---|---|---|---|---|");
        for (name, v) in ["liquid side", "gas side"].iter().zip(&sides) {
            if v.is_empty() {
                continue;
            }
            let cell = |j: usize| {
                let (lo, hi) =
                    v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t[j]), hi.max(t[j])));
                format!("{:+.4} ({lo:+.4} to {hi:+.4})", side_mean(v, j))
            };
            let _ = writeln!(out, "| {name} | {} | {} | {} | {} | {} |", v.len(), cell(0), cell(1), cell(2), cell(3));
        }
    }
    let all = [0, 1].map(|s| if sides[s].is_empty() { f64::NAN } else { side_mean(&sides[s], 0) });
    let what = if profile { "Gas side − liquid side (means over the cuts)" } else { "Gas side − liquid side" };
    let c = &scene.contact;
    if c.mode == ContactMode::A {
        let _ = writeln!(
            out,
            "\n{what}: {:+.4}. Young's σ_GS − σ_LS = {:+.4}; half of it {:+.4}.",
            all[1] - all[0],
            c.sigma_gs - c.sigma_ls,
            0.5 * (c.sigma_gs - c.sigma_ls)
        );
    } else {
        let _ = writeln!(out, "\n{what}: {:+.4}.", all[1] - all[0]);
    }
    out
}

fn write_csv(path: &Path, pos: &[[f64; 2]], phase: &[u32], split: &[Split]) -> Result<(), String> {
    let mut s = String::from("id,x,y,phase");
    for t in TERM_NAMES {
        for p in PARTNER_NAMES {
            let p = p.replace(' ', "_");
            let _ = write!(s, ",{t}_{p}_x,{t}_{p}_y");
        }
    }
    s.push('\n');
    for (i, sp) in split.iter().enumerate() {
        let _ = write!(s, "{i},{:e},{:e},{}", pos[i][0], pos[i][1], phase[i]);
        for row in sp {
            for f in row {
                let _ = write!(s, ",{:e},{:e}", f[0], f[1]);
            }
        }
        s.push('\n');
    }
    std::fs::write(path, s).map_err(|e| format!("--csv {}: {e}", path.display()))
}

/// One table row per term (and their sum) of a split's component `k`.
fn term_rows(out: &mut String, label: &str, s: &Split, k: usize) {
    for (t, name) in TERM_NAMES.iter().enumerate() {
        let row: f64 = s[t].iter().map(|f| f[k]).sum();
        let _ = writeln!(
            out,
            "| {label} | {name} | {:+.4} | {:+.4} | {:+.4} | {:+.4} |",
            s[t][0][k], s[t][1][k], s[t][2][k], row
        );
    }
    let by_partner: Vec<f64> = (0..3).map(|p| (0..3).map(|t| s[t][p][k]).sum()).collect();
    let _ = writeln!(
        out,
        "| {label} | **all** | {:+.4} | {:+.4} | {:+.4} | **{:+.4}** |",
        by_partner[0],
        by_partner[1],
        by_partner[2],
        total(s)[k]
    );
}

fn markdown(dir: &Path, scene: &Scene, states: &[StateBalance], x_c: f64, o: &ForceOptions, w: &Window) -> String {
    let mut out = String::new();
    let sigma = scene.surface_tension.as_ref().map_or(0.0, |s| s.sigma);
    let (first, last) = (&states[0], &states[states.len() - 1]);
    if states.len() == 1 {
        let _ = writeln!(out, "# Force balance of `{}`, step {} (t = {:.4})\n", dir.display(), last.step, last.t);
    } else {
        let _ = writeln!(
            out,
            "# Force balance of `{}`, mean over the {} snapshots from step {} to step {} (t = {:.4} to {:.4})\n",
            dir.display(),
            states.len(),
            first.step,
            last.step,
            first.t,
            last.t
        );
    }
    let c = &scene.contact;
    let model = match c.mode {
        ContactMode::A => format!(
            "Mode A, σ_LG = {sigma}, σ_LS = {}, σ_GS = {} (Young: σ_GS − σ_LS = {:+.4})",
            c.sigma_ls,
            c.sigma_gs,
            c.sigma_gs - c.sigma_ls
        ),
        ContactMode::B => format!(
            "Mode B, σ_LG = {sigma}, θ_d = {}° (σ_LG cos θ_d = {:+.4})",
            c.theta_deg,
            sigma * c.theta_deg.to_radians().cos()
        ),
        ContactMode::None => format!("no contact model, σ = {sigma}"),
    };
    let _ = writeln!(out, "Scene `{}`, nx = {}, {model}.", scene.name, scene.domain.nx);
    let _ = writeln!(
        out,
        "Window: fluid particles with |x − {x_c:.5}| ≤ {}Δx{} and 0 < y − y_w ≤ {}Δx. Forces are m_i·a per unit depth, split by the pair's partner; a pair's force on i alone (its partner's share is not in the window unless the partner is). Pairs inside the window cancel in its sums; what is left is what crosses its edges.\n",
        o.half_width_dx,
        if states.len() > 1 && o.at.is_none() { " (the mean centre: each state's window is centred on its own contact point; sums are means over the states)" } else if states.len() > 1 { " (sums are means over the states)" } else { "" },
        o.height_dx
    );
    for (k, axis) in
        [(0, "x (along the wall; + = towards the gas side of the right contact line)"), (1, "y (normal to the wall)")]
    {
        let _ = writeln!(out, "## {axis}\n");
        let _ =
            writeln!(out, "| particles | term | same phase | other phase | wall | sum |\n|---|---|---|---|---|---|");
        term_rows(&mut out, "liquid", &w.of_phases(&[0]), k);
        term_rows(&mut out, "gas", &w.of_phases(&[1]), k);
        term_rows(&mut out, "both", &w.of_phases(&[0, 1]), k);
        out.push('\n');
    }
    let _ = writeln!(out, "## x by row above the wall\n");
    let mut head = String::from("| row | phase | n |");
    let mut rule = String::from("|---|---|---|");
    for t in TERM_NAMES {
        for p in ["same", "other", "wall"] {
            let _ = write!(head, " {t} {p} |");
            rule.push_str("---|");
        }
    }
    let _ = writeln!(out, "{head} sum |\n{rule}---|");
    for (row, ph, n, s) in &w.rows {
        let _ = write!(out, "| {row} | {} | {n:.1} |", if *ph == 0 { "liquid" } else { "gas" });
        for term in s {
            for f in term {
                let _ = write!(out, " {:+.4} |", f[0]);
            }
        }
        let _ = writeln!(out, " {:+.4} |", total(s)[0]);
    }
    out
}
