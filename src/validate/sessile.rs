//! Case `sessile-90` (docs/PHYSICS.md §9(b), thesis §4.2.2, Figs. 4.3–4.9): the 90° drop at rest on
//! a no-slip wall, Mode B (thesis method) and Mode A (three coefficients). Contact-angle
//! deviation from 90° by the three §10 methods, liquid kinetic energy, the wall shear-rate
//! profile averaged near t ≈ 4.4 (the last 10 % of a shortened run) and the maximum normal
//! deviation (Fig. 4.9). Thesis: Mode B < 3°, Mode A ±10°, Mode A's peak shear ≈ 160× Mode B's.

use super::committed::{vouched, Committed};
use super::data::{for_each_snapshot_in, normal_deviation_quantiles, read_series, Row as SRow, ShearMean};
use super::report::CaseReport;
use super::{Ctx, ValidateError};

mod band;
mod case;

/// Thesis: Mode B contact-angle deviation bound (degrees).
pub const THESIS_MODE_B_DEV: f64 = 3.0;
/// Thesis: Mode A deviation (degrees).
pub const THESIS_MODE_A_DEV: f64 = 10.0;
/// Thesis: ratio of Mode A's to Mode B's peak wall shear rate.
pub const THESIS_SHEAR_RATIO: f64 = 160.0;
/// Thesis Fig. 4.7 (Mode A): the average shear rate peaks at ≈ 2.5 near the triple point (its
/// axis runs to 2.5).
pub const THESIS_MODE_A_SHEAR_PEAK: f64 = 2.5;
/// Thesis Fig. 4.8 (Mode B): the average shear rate stays below 0.016 (its axis's top).
pub const THESIS_MODE_B_SHEAR_MAX: f64 = 0.016;
/// Half-width of the band around the contact line (fraction of the wall; the drop's edge is at
/// 0.5) over which the mean-flow wall shear near the contact line is taken: two bins each side.
const CONTACT_BAND: f64 = 0.1;

/// The resolution of the sensitivity band of the case's judged rows.
pub const BAND_NX: u32 = 33;
/// The sensitivity band of the case's judged rows: each mode at nx = [`BAND_NX`] under the
/// capillary rule's α × 0.5 / × 1 / × 2 (docs/PHYSICS.md §3.1), as `(run id, α, Mode B)`. Mode B's
/// runs band Mode B's rows; both modes' band the Mode A / Mode B shear ratio.
pub const BAND_RUNS: [(&str, f64, bool); 6] = [
    ("mode-b-nx33-alpha1", 1.0, true),
    ("mode-b-nx33", 2.0, true),
    ("mode-b-nx33-alpha4", 4.0, true),
    ("mode-a-nx33-alpha1", 1.0, false),
    ("mode-a-nx33", 2.0, false),
    ("mode-a-nx33-alpha4", 4.0, false),
];

/// The label of a band run's rows ("Mode B, nx = 33, α = 1").
pub fn band_label(mode_b: bool, alpha: f64) -> String {
    format!("Mode {}, nx = {BAND_NX}, α = {alpha}", if mode_b { "B" } else { "A" })
}

/// What a peak wall shear row measures, after its run's label (`window`: the end window's text,
/// e.g. "t ∈ [4.3, 4.5]"): the quantity of the ratio row's numerator and denominator.
pub fn peak_shear(window: &str) -> String {
    format!("peak wall shear rate, {window} (1/time)")
}

/// Quick-mode overrides of the sessile / relax scenes: 26×26 (13 particles per radius),
/// dt = 1.4e-4 (half the CFL limit there), a series row every 100 steps.
pub fn quick_sets() -> Vec<String> {
    let mut sets = crate::scene::capillary::sets_at(&crate::scene::builtin::sessile(90.0), 26);
    sets.extend(["time.dt=1.4e-4".into(), "output.every=100".into()]);
    sets
}

/// The averaging window of the "equilibrium" shear profile: around t = 4.4 when the run
/// reaches 4.6, else its last 10 %.
pub fn shear_window(t_end: f64) -> (f64, f64, String) {
    if t_end >= 4.6 {
        (4.3, 4.5, "t ∈ [4.3, 4.5]".into())
    } else {
        (0.9 * t_end, t_end, format!("last 10 %: t ∈ [{:.3}, {:.3}]", 0.9 * t_end, t_end))
    }
}

/// Δx, y_w and the wall x extent of a sessile-type run.
pub fn geometry(nx: u32) -> (f64, f64, f64) {
    (0.5 / nx as f64, 0.0, 0.5)
}

/// Measured quantities of one sessile-type run.
pub struct Measured {
    /// Series rows.
    pub rows: Vec<SRow>,
    /// Averaged shear profile in the window (mean |γ̇|).
    pub shear: Vec<(f64, f64)>,
    /// The mean flow's shear profile over [`mean_flow_window`]: |time mean of signed γ̇| per bin.
    pub mean_flow: Vec<(f64, f64)>,
    /// Max normal deviation vs t.
    pub normal: Vec<(f64, f64)>,
    /// Per snapshot with counted particles: t and the median, 90th percentile and maximum of
    /// the normal deviations (degrees).
    pub normal_quantiles: Vec<(f64, [f64; 3])>,
    /// Averaged shear profile (mean |γ̇|) over [`startup_window`].
    pub startup: Vec<(f64, f64)>,
}

/// The start-up window: every snapshot after t = 0 up to t = 1 (or the run's end), where the
/// modes differ most (the thesis's kinetic energies, Figs. 4.5–4.6). The thesis does not say
/// over which time Figs. 4.7–4.8 average.
pub fn startup_window(t_end: f64) -> (f64, f64) {
    (1e-12, t_end.min(1.0))
}

/// The window of the mean-flow shear profile: after the start-up (t ≥ 1) to the end of the run
/// (its second half when it ends before t = 2). The thesis's "average shear rate" (Figs. 4.7, 4.8);
/// over ~60 snapshots the particle noise, which dominates |γ̇| in any one snapshot, cancels.
pub fn mean_flow_window(t_end: f64) -> (f64, f64) {
    (if t_end >= 2.0 { 1.0 } else { 0.5 * t_end }, t_end)
}

/// Reads a run back and measures the shear profile in `[a, b]`, the mean-flow shear profile over
/// [`mean_flow_window`], the start-up shear profile ([`startup_window`]) and the normal deviation.
pub fn measure(dir: &std::path::Path, nx: u32, a: f64, b: f64, t_end: f64) -> Measured {
    let (dx, y_w, x_max) = geometry(nx);
    let rows = read_series(dir);
    // Every snapshot read once, in step (so time) order, into each window it lies in.
    let windows = [(a, b), mean_flow_window(t_end), startup_window(t_end)];
    let mut means = [false, true, false].map(|signed| ShearMean::new(dx, y_w, x_max, 20, signed));
    for_each_snapshot_in(dir, &rows, f64::NEG_INFINITY, f64::INFINITY, |s| {
        for ((lo, hi), m) in windows.iter().zip(&mut means) {
            if s.t >= *lo && s.t <= *hi {
                m.add(&s);
            }
        }
    });
    let shear = means[0].profile();
    let mean_flow = means[1].profile().into_iter().map(|(x, g)| (x, g.abs())).collect();
    let normal_quantiles: Vec<(f64, [f64; 3])> =
        normal_deviation_quantiles(dir, &rows, dx, y_w, [0.0, 0.0], 0.25, 3.0 * dx)
            .into_iter()
            .filter_map(|(t, q)| q.map(|q| (t, q)))
            .collect();
    let normal = normal_quantiles.iter().map(|(t, q)| (*t, q[2])).collect();
    let startup = means[2].profile();
    Measured { rows, shear, mean_flow, normal, normal_quantiles, startup }
}

/// The committed tables of the case (their columns: `mode_b` first): the shear profiles and
/// Fig. 4.9's quantiles per snapshot.
pub(super) const SHEAR_TABLE: &str = "wall_shear_profile.csv";
pub(super) const NORMAL_TABLE: &str = "fig4_9_max_normal_deviation.csv";

/// For a reused run with none of its particle snapshots in this checkout: fills `m`'s shear
/// profiles and normal-deviation series from the committed report's tables (each shear profile
/// only where its committed peak row, named in `peaks` as (end window, mean flow, start-up),
/// vouches for it). Returns whether anything was filled.
pub(super) fn from_committed(ctx: &Ctx, mode_b: bool, peaks: [String; 3], m: &mut Measured) -> bool {
    let Some(c) = Committed::load(ctx) else { return false };
    let mode = if mode_b { 1.0 } else { 0.0 };
    let shear = c.table(SHEAR_TABLE, |r| r.len() == 5 && r[0] == mode);
    let [end, flow, startup] = peaks.map(|name| c.value(&name));
    m.shear = vouched(shear.iter().map(|r| (r[1], r[2])).collect(), end);
    m.mean_flow = vouched(shear.iter().map(|r| (r[1], r[3])).collect(), flow);
    m.startup = vouched(shear.iter().map(|r| (r[1], r[4])).collect(), startup);
    m.normal_quantiles =
        c.table(NORMAL_TABLE, |r| r.len() == 5 && r[0] == mode).iter().map(|r| (r[1], [r[2], r[3], r[4]])).collect();
    m.normal = m.normal_quantiles.iter().map(|(t, q)| (*t, q[2])).collect();
    !(m.shear.is_empty() && m.mean_flow.is_empty() && m.startup.is_empty() && m.normal.is_empty())
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    super::executor::execute(ctx, &mut case::Sessile::new(ctx))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::report::Row;
    use crate::validate::ValidateOptions;

    #[test]
    fn a_reused_run_without_snapshots_takes_the_committed_tables_its_peak_rows_vouch_for() {
        let dir = tempfile::tempdir().unwrap();
        let opts = ValidateOptions { out: dir.path().to_path_buf(), ..ValidateOptions::default() };
        let ctx = Ctx::new(&opts, "sessile-90");
        std::fs::create_dir_all(&ctx.dir).unwrap();
        let names = ["end", "flow", "startup"].map(|w| format!("Mode B: peak {w}"));
        let mut rep = CaseReport::new("sessile-90", "test", false);
        // the end window's and the start-up's peaks match the table; the mean flow's does not
        for (name, v) in names.iter().zip([0.5, 9.0, 0.7]) {
            rep.rows.push(Row::new(name, v, 4, None, None));
        }
        std::fs::write(ctx.path("case.json"), serde_json::to_string(&rep).unwrap()).unwrap();
        let shear = "mode_b,x,a,b,c\n1,0.025,0.5,0.2,0.7\n1,0.075,0.1,0.3,0.1\n0,0.025,5,5,5\n";
        std::fs::write(ctx.path(SHEAR_TABLE), shear).unwrap();
        std::fs::write(ctx.path(NORMAL_TABLE), "mode_b,t,med,p90,max\n1,4.3,2,6,9.5\n0,4.3,3,7,12\n1,4.4,2,5,7.5\n")
            .unwrap();
        let mut m = Measured {
            rows: Vec::new(),
            shear: Vec::new(),
            mean_flow: Vec::new(),
            normal: Vec::new(),
            normal_quantiles: Vec::new(),
            startup: Vec::new(),
        };
        assert!(from_committed(&ctx, true, names.clone(), &mut m));
        assert_eq!(m.shear, vec![(0.025, 0.5), (0.075, 0.1)]);
        assert!(m.mean_flow.is_empty(), "its peak row is another run's");
        assert_eq!(m.startup, vec![(0.025, 0.7), (0.075, 0.1)]);
        assert_eq!(m.normal, vec![(4.3, 9.5), (4.4, 7.5)], "Mode B's rows only");
        assert_eq!(m.normal_quantiles[1].1, [2.0, 5.0, 7.5]);
        // no committed report: nothing filled
        std::fs::remove_file(ctx.path("case.json")).unwrap();
        let mut empty = Measured { normal: Vec::new(), ..m };
        assert!(!from_committed(&ctx, true, names, &mut empty) && empty.normal.is_empty());
    }
}
