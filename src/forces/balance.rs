//! Force balance of a saved state: every fluid particle's pair forces split by term (pressure,
//! viscous, surface) and by partner (same fluid phase, other fluid phase, wall), taken from the
//! very walk the solver sums ([`momentum::acceleration_pairs`]); and their sums over a window
//! around a contact point, row by row above the wall. It answers "which pairs pull the contact
//! line, and how hard" (`sphlab forces`).

use crate::backend::SolverError;
use crate::cpu::momentum::{acceleration_pairs, PairTerm};
use crate::cpu::CpuSolver;
use crate::exec::Exec;
use crate::neighbours::SearchKind;
use crate::real::{Real, V2};
use crate::scene::build::{build_layout, WALL};
use crate::scene::Scene;

/// The force terms split out, in this order.
pub const TERMS: [PairTerm; 3] = [PairTerm::Pressure, PairTerm::Viscous, PairTerm::Surface];

/// Names of [`TERMS`].
pub const TERM_NAMES: [&str; 3] = ["pressure", "viscous", "surface"];

/// Who the partner j of a pair is, seen from fluid particle i.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    /// A fluid particle of i's phase (images included).
    Same = 0,
    /// A fluid particle of another phase.
    Other = 1,
    /// A wall particle.
    Wall = 2,
}

/// Names of the partners, by [`Partner`] index.
pub const PARTNER_NAMES: [&str; 3] = ["same phase", "other phase", "wall"];

/// Forces (`m_i a`, per unit depth) on one particle or a set: `[term][partner]` as x, y.
pub type Split = [[[f64; 2]; 3]; 3];

/// The zero split.
pub const ZERO: Split = [[[0.0; 2]; 3]; 3];

/// Adds `b` into `a`.
pub fn add_into(a: &mut Split, b: &Split) {
    for t in 0..3 {
        for p in 0..3 {
            a[t][p][0] += b[t][p][0];
            a[t][p][1] += b[t][p][1];
        }
    }
}

/// The sum over every term and partner.
pub fn total(s: &Split) -> [f64; 2] {
    let mut t = [0.0; 2];
    for row in s {
        for f in row {
            t[0] += f[0];
            t[1] += f[1];
        }
    }
    t
}

/// The split of every fluid particle's pair forces at the solver's last evaluation (call
/// [`CpuSolver::evaluate`] first). Summed over terms and partners, a particle's split is
/// `m_i (a_i − g − a_LJ)`.
pub fn split_forces<T: Real>(s: &CpuSolver<T>) -> Vec<Split> {
    let c = s.ctx();
    (0..s.n_fluid)
        .map(|i| {
            let mut out = ZERO;
            acceleration_pairs(&c, &s.f, i, |j, _, term, v| {
                let Some(t) = TERMS.iter().position(|&x| x == term) else { return };
                let p = if j >= s.n_fluid {
                    Partner::Wall
                } else if s.phase[j] == s.phase[i] {
                    Partner::Same
                } else {
                    Partner::Other
                };
                out[t][p as usize][0] += v.x.f64();
                out[t][p as usize][1] += v.y.f64();
            });
            out
        })
        .collect()
}

/// The force across the vertical line `x = x_cut`, by row above the wall
/// (`⌊(y − y_w)/Δx⌋`): for the fluid particles right of the line, the pair forces on them from
/// every particle left of it (fluid, images at their image positions, and wall), as
/// `(row, [fx, fy] per term of TERMS)` sorted by row; one walk gives every term. In a row of
/// uniform fluid at pressure p this is about pΔx; a tension band crossing the line lowers it by
/// its tension ([`band_tension`]). The wall partners count: without them, rows next to a wall
/// miss the wall's share of the pressure pairs and read a tension where there is none.
pub fn cut_rows<T: Real>(s: &CpuSolver<T>, x_cut: f64, dx: f64, y_w: f64) -> Vec<(u32, [[f64; 2]; 3])> {
    let c = s.ctx();
    let mut rows: Vec<(u32, [[f64; 2]; 3])> = Vec::new();
    for i in 0..s.n_fluid {
        let (x, d) = (s.pos[i].x.f64(), s.pos[i].y.f64() - y_w);
        if x <= x_cut || d <= 0.0 {
            continue;
        }
        let row = (d / dx).floor() as u32;
        let k = match rows.iter().position(|r| r.0 == row) {
            Some(k) => k,
            None => {
                rows.push((row, [[0.0; 2]; 3]));
                rows.len() - 1
            }
        };
        let f = &mut rows[k].1;
        acceleration_pairs(&c, &s.f, i, |_, xj, term, v| {
            if let Some(t) = TERMS.iter().position(|&x| x == term) {
                if xj.x.f64() <= x_cut {
                    f[t][0] += v.x.f64();
                    f[t][1] += v.y.f64();
                }
            }
        });
    }
    rows.sort_by_key(|r| r.0);
    rows
}

/// The tension a band of rows carries across a cut in the `terms` chosen: `−Σ_band (F_row −
/// F̄_bulk)`, with `F_row` the x-force of [`cut_rows`] summed over `terms` and `F̄_bulk` its mean
/// over the `bulk` rows (uniform fluid). A band at lower pressure than the bulk, or pulling,
/// gives a positive tension. None when a row of either range is missing.
pub fn band_tension(
    rows: &[(u32, [[f64; 2]; 3])],
    terms: &[PairTerm],
    band: std::ops::Range<u32>,
    bulk: std::ops::Range<u32>,
) -> Option<f64> {
    let pick: Vec<usize> = terms.iter().filter_map(|t| TERMS.iter().position(|x| x == t)).collect();
    let get = |r: u32| rows.iter().find(|x| x.0 == r).map(|x| pick.iter().map(|&t| x.1[t][0]).sum::<f64>());
    let bulk_f: Option<Vec<f64>> = bulk.clone().map(get).collect();
    let bulk_f = bulk_f.filter(|v| !v.is_empty())?;
    let mean = bulk_f.iter().sum::<f64>() / bulk_f.len() as f64;
    let band_f: Option<Vec<f64>> = band.map(get).collect();
    Some(-band_f?.iter().map(|f| f - mean).sum::<f64>())
}

/// A saved state to evaluate: positions, velocities and phases of every particle, in the
/// order of the scene's layout (what `particles_*.csv` holds).
pub struct State<'a> {
    /// Positions.
    pub pos: &'a [[f64; 2]],
    /// Velocities.
    pub vel: &'a [[f64; 2]],
    /// Fluid phase or [`WALL`].
    pub phase: &'a [u32],
}

/// An f64 CPU solver of `scene` placed at `state` and evaluated once. The state must be one of
/// this scene's runs: the same particle count, phases, and wall particles where the layout puts
/// them (else an error naming the first mismatch).
pub fn evaluate_state(scene: &Scene, state: &State, exec: Exec) -> Result<CpuSolver<f64>, String> {
    let layout = build_layout(scene).map_err(|e| e.to_string())?;
    let n = layout.pos.len();
    if state.pos.len() != n || state.vel.len() != n || state.phase.len() != n {
        return Err(format!(
            "the state has {} particles, the scene's layout {n}: not a run of this scene",
            state.pos.len()
        ));
    }
    let tol = 1e-9 * scene.domain.dx();
    for i in 0..n {
        if state.phase[i] != layout.phase[i] {
            return Err(format!(
                "particle {i}: phase {} in the state, {} in the layout",
                state.phase[i], layout.phase[i]
            ));
        }
        let moved = (state.pos[i][0] - layout.pos[i][0]).abs().max((state.pos[i][1] - layout.pos[i][1]).abs());
        if layout.phase[i] == WALL && moved > tol {
            return Err(format!("wall particle {i} is {moved:e} from its place in the layout"));
        }
    }
    let mut s = CpuSolver::<f64>::new(scene, &layout, exec, SearchKind::Cells);
    for i in 0..n {
        s.pos[i] = V2::from_f64(state.pos[i][0], state.pos[i][1]);
        s.vel[i] = V2::from_f64(state.vel[i][0], state.vel[i][1]);
    }
    s.evaluate().map_err(|e: SolverError| e.to_string())?;
    Ok(s)
}

/// The sums of a window: fluid particles with `|x − x_c| ≤ half_width` and
/// `0 < y − y_w ≤ height`, by row above the wall (`⌊(y − y_w)/Δx⌋`) and by the particle's own
/// phase.
#[derive(Clone, Debug, PartialEq)]
pub struct Window {
    /// `(row, phase, particles, split)`, sorted by row then phase (the particle count is a mean
    /// after [`Window::mean`]).
    pub rows: Vec<(u32, u32, f64, Split)>,
}

impl Window {
    /// Sums `split` (one per fluid particle, as [`split_forces`]) over the window.
    #[allow(clippy::too_many_arguments, reason = "the window's geometry is named at every call site")]
    pub fn sum(
        pos: &[[f64; 2]],
        phase: &[u32],
        split: &[Split],
        x_c: f64,
        half_width: f64,
        y_w: f64,
        height: f64,
        dx: f64,
    ) -> Self {
        let mut rows: Vec<(u32, u32, f64, Split)> = Vec::new();
        for (i, s) in split.iter().enumerate() {
            let (x, d) = (pos[i][0], pos[i][1] - y_w);
            if (x - x_c).abs() > half_width || d <= 0.0 || d > height {
                continue;
            }
            let row = (d / dx).floor() as u32;
            match rows.iter_mut().find(|r| r.0 == row && r.1 == phase[i]) {
                Some(r) => {
                    r.2 += 1.0;
                    add_into(&mut r.3, s);
                }
                None => rows.push((row, phase[i], 1.0, *s)),
            }
        }
        rows.sort_by_key(|r| (r.0, r.1));
        Self { rows }
    }

    /// The mean of the same window at several states: each row's sum and count averaged over
    /// all of them, a state without that row counting zero (so the window's totals are the
    /// means of its totals).
    pub fn mean(ws: &[Window]) -> Window {
        let mut rows: Vec<(u32, u32, f64, Split)> = Vec::new();
        for w in ws {
            for r in &w.rows {
                match rows.iter_mut().find(|x| x.0 == r.0 && x.1 == r.1) {
                    Some(x) => {
                        x.2 += r.2;
                        add_into(&mut x.3, &r.3);
                    }
                    None => rows.push(*r),
                }
            }
        }
        let k = ws.len().max(1) as f64;
        for r in &mut rows {
            r.2 /= k;
            for t in r.3.iter_mut() {
                for f in t.iter_mut() {
                    f[0] /= k;
                    f[1] /= k;
                }
            }
        }
        rows.sort_by_key(|r| (r.0, r.1));
        Window { rows }
    }

    /// The sum over the rows of the phases in `phases`.
    pub fn of_phases(&self, phases: &[u32]) -> Split {
        let mut s = ZERO;
        for r in self.rows.iter().filter(|r| phases.contains(&r.1)) {
            add_into(&mut s, &r.3);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::Backend;
    use crate::scene::{builtin, overrides::apply_overrides};

    fn relaxed(mode: &str, steps: usize) -> (Scene, CpuSolver<f64>) {
        let sc = apply_overrides(
            &builtin::builtin("relax-60").unwrap(),
            &["domain.nx=21".to_string(), format!("contact.mode={mode}")],
        )
        .unwrap();
        let layout = build_layout(&sc).unwrap();
        let mut s = CpuSolver::<f64>::new(&sc, &layout, Exec::Serial, SearchKind::Cells);
        for _ in 0..steps {
            s.step().unwrap();
        }
        (sc, s)
    }

    /// Summed over terms and partners, each particle's split is m_i (a_i − g): the split
    /// loses or doubles no pair (the scene has no Lennard-Jones walls).
    #[test]
    fn a_particles_split_adds_up_to_its_acceleration() {
        for mode in ["a", "b"] {
            let (_, mut s) = relaxed(mode, 20);
            s.evaluate().unwrap();
            let split = split_forces(&s);
            let g = [s.model.gravity.x, s.model.gravity.y];
            let mut worst: f64 = 0.0;
            let mut scale: f64 = 0.0;
            for (i, sp) in split.iter().enumerate() {
                let t = total(sp);
                let m = s.f.mass[i];
                for k in 0..2 {
                    let a = [s.f.acc[i].x, s.f.acc[i].y][k] - g[k];
                    worst = worst.max((t[k] / m - a).abs());
                    scale = scale.max(a.abs());
                }
            }
            assert!(scale > 0.0, "mode {mode}: no force at all");
            assert!(worst <= 1e-12 * scale, "mode {mode}: split off its acceleration by {worst:e} (scale {scale:e})");
        }
    }

    /// Newton's third law of the pair forms: summed over every fluid particle, the fluid–fluid
    /// pairs (same and other phase) of each term cancel, away from mirror images; the wall
    /// pairs do not. The relax-60 half drop has a mirror at x = 0, which transmits x-forces, so
    /// the check is on y, plus x for the stress term far from the mirror in a full scene.
    #[test]
    fn fluid_pairs_cancel_in_the_sum_over_the_fluid() {
        let (sc, s) = relaxed("a", 20);
        let state_pos: Vec<[f64; 2]> = s.pos.iter().map(|p| [p.x, p.y]).collect();
        let state_vel: Vec<[f64; 2]> = s.vel.iter().map(|v| [v.x, v.y]).collect();
        let state = State { pos: &state_pos, vel: &state_vel, phase: &s.phase };
        let e = evaluate_state(&sc, &state, Exec::Serial).unwrap();
        let split = split_forces(&e);
        let mut sum = ZERO;
        for sp in &split {
            add_into(&mut sum, sp);
        }
        for t in 0..3 {
            let fluid = sum[t][0][1] + sum[t][1][1];
            let scale: f64 = split.iter().map(|sp| sp[t][0][1].abs() + sp[t][1][1].abs()).sum();
            assert!(scale > 0.0, "{}: no fluid pair force", TERM_NAMES[t]);
            assert!(fluid.abs() <= 1e-9 * scale, "{}: fluid pairs leave {fluid:e} of {scale:e} in y", TERM_NAMES[t]);
        }
        // The bottom wall's pressure pairs push the fluid of the lower half up, not zero.
        let up: f64 = split.iter().zip(&e.pos).filter(|(_, p)| p.y < 0.25).map(|(sp, _)| sp[0][2][1]).sum();
        assert!(up > 0.0, "bottom wall pressure pairs give {up:e} in y");
    }

    /// A state of another scene, or with a wall particle moved, is refused with the reason.
    #[test]
    fn a_state_of_another_scene_is_refused() {
        let (sc, s) = relaxed("a", 0);
        let mut pos: Vec<[f64; 2]> = s.pos.iter().map(|p| [p.x, p.y]).collect();
        let vel = vec![[0.0; 2]; pos.len()];
        let n_fluid = s.n_fluid;
        pos[n_fluid][0] += 0.1 * sc.domain.dx();
        let err = evaluate_state(&sc, &State { pos: &pos, vel: &vel, phase: &s.phase }, Exec::Serial).err().unwrap();
        assert!(err.contains(&format!("wall particle {n_fluid}")), "{err}");
        let short = &pos[1..];
        let err = evaluate_state(&sc, &State { pos: short, vel: &vel[1..], phase: &s.phase[1..] }, Exec::Serial)
            .err()
            .unwrap();
        assert!(err.contains("not a run of this scene"), "{err}");
    }

    /// The window sums each particle once, into its row and phase.
    #[test]
    fn window_rows_hold_their_particles() {
        let mut a = ZERO;
        a[2][1] = [1.0, 2.0];
        let pos = [[0.0, 0.15], [0.05, 0.25], [0.5, 0.15], [0.0, 0.05], [0.0, -0.05]];
        let phase = [0, 1, 0, 0, 0];
        let w = Window::sum(&pos, &phase, &[a; 5], 0.0, 0.1, 0.0, 0.3, 0.1);
        let got: Vec<(u32, u32, f64)> = w.rows.iter().map(|r| (r.0, r.1, r.2)).collect();
        assert_eq!(got, vec![(0, 0, 1.0), (1, 0, 1.0), (2, 1, 1.0)]);
        assert_eq!(w.of_phases(&[0])[2][1], [2.0, 4.0]);
        assert_eq!(w.of_phases(&[0, 1])[2][1], [3.0, 6.0]);
        // The mean with a state holding only the gas row: rows absent there count zero.
        let v = Window::sum(&pos[1..2], &phase[1..2], &[a], 0.0, 0.1, 0.0, 0.3, 0.1);
        let m = Window::mean(&[w.clone(), v]);
        let got: Vec<(u32, u32, f64)> = m.rows.iter().map(|r| (r.0, r.1, r.2)).collect();
        assert_eq!(got, vec![(0, 0, 0.5), (1, 0, 0.5), (2, 1, 1.0)]);
        assert_eq!(m.of_phases(&[0])[2][1], [1.0, 2.0]);
        assert_eq!(m.of_phases(&[1])[2][1], [1.0, 2.0]);
    }
}
