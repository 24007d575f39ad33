//! The convergence case under the tangential stress form (docs/PHYSICS.md §5.3): the lattice
//! runs again at nx = 33, 45 and 65 with `surface_tension.tensor = "tangential"`, the scene and
//! the capillary rule otherwise unchanged. The traceless form's band carries half its tension
//! as a pressure deficit, a density deficit of about the rule's ε at every Δx. The tangential
//! form's band needs none. What is left is the compressibility of the Laplace jump,
//! σκ/(ρ0c0²), which the rule's c0 ∝ Δx^(−1/2) makes fall as Δx.

use super::super::band_rows::{at_end, BAND};
use super::super::judge::{ANGLE_TOL_DEG, YOUNG_DEG};
use super::super::report::{write_csv, CaseReport, Row};
use super::super::{Ctx, RunSpec, ValidateError};
use super::realisations::{band_density_row, end_values, End};
use std::path::Path;

/// Resolutions of the tangential runs.
pub const TANGENTIAL_NX: [u32; 3] = [33, 45, 65];

/// The override that selects the form.
pub const TENSOR_SET: &str = "surface_tension.tensor=\"tangential\"";

/// The lattice run's spec at `nx` with the tangential form.
fn spec(nx: u32, t_end: f64) -> RunSpec<'static> {
    let mut s = super::spec(nx, false, t_end);
    s.sets.push(TENSOR_SET.into());
    s.id = format!("nx{nx}-tangential");
    s
}

/// Runs (or reuses) the tangential runs and adds their rows and verdicts; `lattice` holds the
/// traceless lattice runs' end states by resolution.
pub fn add(ctx: &Ctx, rep: &mut CaseReport, lattice: &[(u32, End)], t_end: f64) -> Result<(), ValidateError> {
    let (wa, wb, wtext) = super::super::sessile::shear_window(t_end);
    let mut ends = Vec::new();
    let mut csv = Vec::new();
    for nx in TANGENTIAL_NX {
        let Some(rec) = super::run_or_skip(ctx, rep, &spec(nx, t_end), &[])? else { continue };
        let e = end_values(Path::new(&rec.dir), nx, wa, wb);
        let what = format!("tangential form at Δx = 0.5/{nx}");
        rep.rows.push(Row::new(
            &format!("{what}: θ circle fit, mean over {wtext} (deg)"),
            e.theta,
            2,
            None,
            Some(YOUNG_DEG),
        ));
        rep.rows.push(Row::new(
            &format!("{what}: D/D0 at the wall, mean over {wtext}"),
            e.spread,
            3,
            None,
            Some(super::super::relax::analytic_spread()),
        ));
        rep.rows.push(Row::new(&format!("{what}: max |ρ/ρ0 − 1| for t ≥ 1"), e.density, 4, None, None));
        if let Some(b) = e.band {
            rep.rows.push(band_density_row(&what, &[b]));
        }
        csv.push(vec![nx as f64, e.theta, e.spread, e.density, e.band.map_or(f64::NAN, |b| b.band_max)]);
        ends.push((nx, e));
        rep.runs.push(rec);
    }
    rep.notes.push(format!(
        "Tangential form (`{TENSOR_SET}`, docs/PHYSICS.md §5.3; CPU only): the lattice runs again at nx = {}, \
         the scene, p_b and c0 unchanged. Stated before the runs: its max |ρ/ρ0 − 1| for t ≥ 1 falls at every \
         refinement; its last state's maximum in the interface band is below half the traceless form's at \
         each resolution run in both; and θ stays within 3° of 60° at every resolution.",
        TANGENTIAL_NX.map(|k| k.to_string()).join(", ")
    ));
    rep.rows.extend(verdicts(&ends, lattice));
    band(ctx, rep, t_end)?;
    if !ends.is_empty() {
        write_csv(
            ctx,
            rep,
            "tangential.csv",
            "nx,theta_circle_end,spread_end,max_density_error_t_ge_1,band_max_last_state",
            &csv,
        )?;
    }
    Ok(())
}

/// The runs of the verdicts' sensitivity band: the lattice runs in both forms again under the
/// capillary rule's α × 0.5 and × 2 (`nx<nx>-alpha1`, `-alpha4` and the same with
/// `-tangential`), the rule's α in place of the named p_b and c0 (c0 does not depend on α). The
/// judge reads their series (`judge::sensitivity::lattice_alpha_band`).
fn band(ctx: &Ctx, rep: &mut CaseReport, t_end: f64) -> Result<(), ValidateError> {
    for k in 0..BAND.len() {
        for nx in TANGENTIAL_NX {
            for base in [super::spec(nx, false, t_end), spec(nx, t_end)] {
                if let Some(rec) = super::run_or_skip(ctx, rep, &at_end(&base, k), &[])? {
                    rep.runs.push(rec);
                }
            }
        }
    }
    Ok(())
}

/// The three verdicts stated before the runs (none without two resolutions).
fn verdicts(ends: &[(u32, End)], lattice: &[(u32, End)]) -> Vec<Row> {
    if ends.len() < 2 {
        return Vec::new();
    }
    let nxs: Vec<String> = ends.iter().map(|(nx, _)| nx.to_string()).collect();
    let nxs = nxs.join(", ");
    let rho: Vec<f64> = ends.iter().map(|(_, e)| e.density).collect();
    let falls = rho.windows(2).all(|w| w[1] < w[0]);
    let text: Vec<String> = rho.iter().map(|v| format!("{v:.4}")).collect();
    let mut rows = vec![Row::new(
        &format!("tangential form: max |ρ/ρ0 − 1| for t ≥ 1 with refinement, nx = {nxs}"),
        *rho.last().unwrap_or(&f64::NAN),
        4,
        None,
        None,
    )
    .sphlab_text(text.join(" → "))
    .check(falls, "falls at every refinement")];
    let pairs: Vec<(u32, f64, f64)> = ends
        .iter()
        .filter_map(|(nx, e)| {
            let t = lattice.iter().find(|(n, _)| n == nx)?.1.band?;
            Some((*nx, e.band?.band_max, t.band_max))
        })
        .collect();
    if !pairs.is_empty() {
        let half = pairs.iter().all(|(_, tan, tr)| *tan < 0.5 * tr);
        let text: Vec<String> = pairs.iter().map(|(nx, a, b)| format!("nx {nx}: {a:.4} vs {b:.4}")).collect();
        let worst = pairs.iter().map(|(_, a, b)| a / b).fold(f64::NAN, f64::max);
        rows.push(
            Row::new(
                "tangential form: last state's band max over the traceless form's (worst resolution)",
                worst,
                3,
                None,
                None,
            )
            .sphlab_text(text.join("; "))
            .check(half, "below one half at each resolution run in both forms"),
        );
    }
    let off: Vec<f64> = ends.iter().map(|(_, e)| (e.theta - YOUNG_DEG).abs()).collect();
    let text: Vec<String> = off.iter().map(|v| format!("{v:.2}")).collect();
    rows.push(
        Row::new(
            &format!("tangential form: |θ − 60°| at nx = {nxs} (deg)"),
            off.iter().copied().fold(f64::NAN, f64::max),
            2,
            None,
            Some(0.0),
        )
        .sphlab_text(text.join(", "))
        .check(off.iter().all(|v| *v < ANGLE_TOL_DEG), "within 3° at every resolution"),
    );
    rows
}

#[cfg(test)]
mod tests {
    use super::super::band_density::BandDensity;
    use super::*;

    fn end(theta: f64, density: f64, band_max: f64) -> End {
        let band = Some(BandDensity { band_max, outside_max: 0.0, outside_mean: 0.0 });
        End { theta, two_point: f64::NAN, spread: 1.385, density, band }
    }

    fn verdict_list(ends: &[(u32, End)], lattice: &[(u32, End)]) -> Vec<bool> {
        verdicts(ends, lattice).iter().map(|r| r.verdict.starts_with("pass")).collect()
    }

    #[test]
    fn the_tangential_verdicts_pass_only_as_stated() {
        let lattice = [(33, end(60.0, 0.014, 0.012)), (45, end(60.5, 0.015, 0.013))];
        // falling density, band below half, angles within 3°
        let good = [(33, end(60.4, 0.004, 0.003)), (45, end(61.0, 0.003, 0.002))];
        assert_eq!(verdict_list(&good, &lattice), [true, true, true]);
        // density rising, a band at two thirds of the traceless one, an angle 3.5° off
        let bad = [(33, end(60.4, 0.004, 0.008)), (45, end(63.5, 0.005, 0.002))];
        assert_eq!(verdict_list(&bad, &lattice), [false, false, false]);
        // one resolution gives no verdict
        assert!(verdicts(&good[..1], &lattice).is_empty());
    }
}
