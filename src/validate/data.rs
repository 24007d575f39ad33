//! Reading a run back for validation: `series.csv` as columns, particle snapshots
//! (`particles_<step>.csv`, walls phase −1 → [`WALL`], read one at a time so an analysis never
//! holds a whole run) and small statistics helpers.

use crate::scene::build::WALL;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// One `series.csv` row: the row type `sphlab run` writes.
pub type Row = crate::run::SeriesRow;

/// Reads `dir/series.csv` (rows that fail to parse, e.g. a half-written last line, end it).
pub fn read_series(dir: &Path) -> Vec<Row> {
    let Ok(mut r) = csv::Reader::from_path(dir.join("series.csv")) else {
        return Vec::new();
    };
    r.deserialize::<Row>().map_while(Result::ok).collect()
}

/// `(t, f(row))` for the rows where `f` gives a finite value.
pub fn col(rows: &[Row], f: impl Fn(&Row) -> Option<f64>) -> Vec<(f64, f64)> {
    rows.iter().filter_map(|r| f(r).filter(|v| v.is_finite()).map(|v| (r.t, v))).collect()
}

/// Mean and (population) standard deviation of the values with `t` in `[a, b]`.
pub fn window_stats(pts: &[(f64, f64)], a: f64, b: f64) -> Option<(f64, f64, usize)> {
    let v: Vec<f64> = pts.iter().filter(|p| p.0 >= a && p.0 <= b).map(|p| p.1).collect();
    if v.is_empty() {
        return None;
    }
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let s = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n).sqrt();
    Some((m, s, v.len()))
}

/// The value at the last point (None if empty).
pub fn last(pts: &[(f64, f64)]) -> Option<f64> {
    pts.last().map(|p| p.1)
}

/// A particle snapshot read back.
#[derive(Clone, Debug, Default)]
pub struct Snap {
    /// Step.
    pub step: u64,
    /// Time (from the series row of the same step; NaN if none).
    pub t: f64,
    /// Positions.
    pub pos: Vec<[f64; 2]>,
    /// Velocities.
    pub vel: Vec<[f64; 2]>,
    /// Phase ([`WALL`] for walls).
    pub phase: Vec<u32>,
    /// Colour gradient.
    pub grad_c: Vec<[f64; 2]>,
    /// Pressure.
    pub p: Vec<f64>,
    /// Density.
    pub rho: Vec<f64>,
}

#[derive(Deserialize)]
struct PRow {
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
    phase: i64,
    gcx: f64,
    gcy: f64,
    p: f64,
    rho: f64,
}

/// The snapshot files of a run, sorted by step.
pub fn snapshot_files(dir: &Path) -> Vec<(u64, PathBuf)> {
    let mut v: Vec<(u64, PathBuf)> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().to_string();
            let step = name.strip_prefix("particles_")?.strip_suffix(".csv")?.parse().ok()?;
            Some((step, e.path()))
        })
        .collect();
    v.sort();
    v
}

/// Reads one snapshot file.
pub fn read_snapshot(path: &Path, step: u64, t: f64) -> Option<Snap> {
    let mut r = csv::Reader::from_path(path).ok()?;
    let mut s = Snap { step, t, ..Default::default() };
    for row in r.deserialize::<PRow>() {
        let p = row.ok()?;
        s.pos.push([p.x, p.y]);
        s.vel.push([p.vx, p.vy]);
        s.phase.push(if p.phase < 0 { WALL } else { p.phase as u32 });
        s.grad_c.push([p.gcx, p.gcy]);
        s.p.push(p.p);
        s.rho.push(p.rho);
    }
    Some(s)
}

/// Calls `f` with every snapshot of a run whose time (from the series rows) lies in `[a, b]`, in
/// step order, read back one at a time: an analysis holds one snapshot, never the whole run.
pub fn for_each_snapshot_in(dir: &Path, rows: &[Row], a: f64, b: f64, mut f: impl FnMut(Snap)) {
    for (step, p) in snapshot_files(dir) {
        let Some(t) = rows.iter().find(|r| r.step == step).map(|r| r.t) else { continue };
        if t >= a && t <= b {
            if let Some(s) = read_snapshot(&p, step, t) {
                f(s);
            }
        }
    }
}

/// Wall shear-rate profile averaged over snapshots (count-weighted per bin), added one snapshot
/// at a time: `(fraction of the wall, mean |γ̇|)` for the non-empty bins, via
/// [`crate::diagnostics::wall_shear_profile`].
pub struct ShearMean {
    dx: f64,
    y_w: f64,
    x_max: f64,
    signed: bool,
    sum: Vec<f64>,
    cnt: Vec<usize>,
}

impl ShearMean {
    /// No snapshot yet; `bins` bins over `[0, x_max]`, the signed shear rate with `signed`.
    pub fn new(dx: f64, y_w: f64, x_max: f64, bins: usize, signed: bool) -> Self {
        ShearMean { dx, y_w, x_max, signed, sum: vec![0.0; bins], cnt: vec![0; bins] }
    }

    /// Adds one snapshot.
    pub fn add(&mut self, s: &Snap) {
        let bins = self.sum.len();
        let prof = crate::diagnostics::wall_shear_profile(
            &s.pos,
            &s.vel,
            &s.phase,
            self.dx,
            self.y_w,
            self.x_max,
            bins,
            self.signed,
        );
        for (b, (_, m, c)) in prof.into_iter().enumerate() {
            self.sum[b] += m * c as f64;
            self.cnt[b] += c;
        }
    }

    /// The mean profile of the snapshots added.
    pub fn profile(&self) -> Vec<(f64, f64)> {
        let (sum, cnt, bins) = (&self.sum, &self.cnt, self.sum.len());
        (0..bins).filter(|&b| cnt[b] > 0).map(|b| ((b as f64 + 0.5) / bins as f64, sum[b] / cnt[b] as f64)).collect()
    }
}

/// [`ShearMean`] of the snapshots of a run with time in `[a, b]`.
#[allow(clippy::too_many_arguments, reason = "the window, the band and the wall geometry are named at every call")]
pub fn mean_shear_profile_in(
    dir: &Path,
    rows: &[Row],
    (a, b): (f64, f64),
    dx: f64,
    y_w: f64,
    x_max: f64,
    bins: usize,
    signed: bool,
) -> Vec<(f64, f64)> {
    let mut m = ShearMean::new(dx, y_w, x_max, bins, signed);
    for_each_snapshot_in(dir, rows, a, b, |s| m.add(&s));
    m.profile()
}

/// The normal deviations (Fig. 4.9) of every snapshot, via
/// [`crate::diagnostics::flow::normal_deviations`]: per snapshot the median, 90th percentile and
/// maximum (degrees; `None` when no particle counts) of the angles between n̂ and the radial
/// direction from `centre`, over the fluid particles within `band` of the circle of radius
/// `radius` about `centre` (the drop's interface band; without it, Mode A's colour gradients at
/// the right and top walls, a third phase there, count too).
pub fn normal_deviation_quantiles(
    dir: &Path,
    rows: &[Row],
    dx: f64,
    y_w: f64,
    centre: [f64; 2],
    radius: f64,
    band: f64,
) -> Vec<(f64, Option<[f64; 3]>)> {
    let mut out = Vec::new();
    for_each_snapshot_in(dir, rows, f64::NEG_INFINITY, f64::INFINITY, |s| {
        out.push({
            let keep: Vec<usize> = (0..s.pos.len())
                .filter(|&i| {
                    let r = (s.pos[i][0] - centre[0]).hypot(s.pos[i][1] - centre[1]);
                    s.phase[i] != WALL && (r - radius).abs() <= band
                })
                .collect();
            let pos: Vec<[f64; 2]> = keep.iter().map(|&i| s.pos[i]).collect();
            let phase: Vec<u32> = keep.iter().map(|&i| s.phase[i]).collect();
            let g: Vec<[f64; 2]> = keep.iter().map(|&i| s.grad_c[i]).collect();
            let mut d = crate::diagnostics::flow::normal_deviations(&pos, &phase, &g, dx, y_w, centre);
            d.sort_by(f64::total_cmp);
            let q = |f: f64| d[((f * d.len() as f64) as usize).min(d.len() - 1)];
            (s.t, (!d.is_empty()).then(|| [q(0.5), q(0.9), d[d.len() - 1]]))
        })
    });
    out
}
