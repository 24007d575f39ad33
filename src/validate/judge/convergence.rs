//! The convergence case's verdicts: the trend rows over the three finest resolutions with their
//! α band and the fixed-p_b runs beside them, and the tangential form's rows with theirs.

use super::super::data::read_series;
use super::super::report::{Band, CaseReport, Row};
use super::{end_angle, falls, sensitivity, ANGLE_TOL_DEG, YOUNG_DEG};
use std::path::Path;

/// The resolutions of the convergence case's rows, finest last, with the row's value.
fn by_resolution(rep: &CaseReport, what: &str) -> Vec<(u32, f64)> {
    let mut v: Vec<(u32, f64)> = rep
        .rows
        .iter()
        .filter(|r| r.quantity.contains(what))
        .filter_map(|r| {
            let nx = r.quantity.strip_prefix("Δx = 0.5/")?.split(':').next()?.parse().ok()?;
            Some((nx, r.value))
        })
        .collect();
    v.sort_by_key(|p| p.0);
    v
}

/// The trend rows of the convergence case: |θ − 60°| and the density error over the three finest
/// resolutions must fall with Δx; with the same at a fixed p_b where a committed run gives it.
pub(super) fn convergence(root: &Path, rep: &mut CaseReport) {
    rep.rows.retain(|r| !r.quantity.starts_with("trend with refinement"));
    let (mut theta_band, mut dens_band) = (None, None);
    let theta = by_resolution(rep, "θ circle fit");
    let fine: Vec<(u32, f64)> = theta.iter().rev().take(3).rev().copied().collect();
    if fine.len() == 3 {
        let err: Vec<f64> = fine.iter().map(|p| (p.1 - YOUNG_DEG).abs()).collect();
        let nxs: Vec<String> = fine.iter().map(|p| p.0.to_string()).collect();
        let fixed = fixed_pb_angle(root, fine[2].0).map_or(String::new(), |t| {
            format!("; at nx = {} before the rule (c0 = 20, p_b = 45 held): {t:.2}° (pb-check/runs)", fine[2].0)
        });
        let nx_list: Vec<u32> = fine.iter().map(|p| p.0).collect();
        theta_band = sensitivity::convergence_alpha_band(root, &nx_list, &err, false);
        let what = format!("|θ − 60°| at nx = {} (deg)", nxs.join(", "));
        rep.rows.push(trend_row(&what, &err, 2, &fixed, "falls at every refinement (convergence to Young's angle)"));
        let by_nx = by_resolution(rep, "max |ρ/ρ0 − 1| for t ≥ 1");
        let dens: Vec<f64> = fine
            .iter()
            .map(|p| by_nx.iter().find(|d| d.0 == p.0).map_or_else(|| max_density_error(root, p.0), |d| d.1))
            .collect();
        if dens.iter().all(|d| d.is_finite()) {
            dens_band = sensitivity::convergence_alpha_band(root, &nx_list, &dens, true);
            let what = format!("max |ρ/ρ0 − 1| for t ≥ 1 at nx = {}", nxs.join(", "));
            let after = format!(" (the runs' series.csv){}", band_note(rep));
            rep.rows.push(trend_row(&what, &dens, 3, &after, "falls at every refinement"));
        }
    }
    let on = "p_b and c0 by the capillary rule at each nx (α = 2, ε = 0.01; docs/PHYSICS.md §3.1), μ = 0.05, \
              Mode B, no-slip, the start (lattice, or jittered by 0.05Δx for the realisations)";
    // The realisations' row is shown the lattice runs' band, not judged by its standard errors.
    let lattice_only = theta_band.clone().map(|b| Band {
        varied: format!("{} (one lattice run per nx and α; not judged by this row's standard errors)", b.varied),
        holds: None,
        ..b
    });
    let bands = [("realisations", &lattice_only), ("|ρ/ρ0 − 1|", &dens_band), ("", &theta_band)];
    qualify_each(rep, "trend with refinement", on, &bands);
    tangential_bands(root, rep);
}

/// A trend row "trend with refinement: `what`", coarse to fine `values` printed to `prec`
/// decimals joined by arrows then `after`, judged by whether they fall at every refinement.
fn trend_row(what: &str, values: &[f64], prec: usize, after: &str, criterion: &str) -> Row {
    let text = values.iter().map(|e| format!("{e:.prec$}")).collect::<Vec<_>>().join(" → ");
    Row::new(&format!("trend with refinement: {what}"), values[values.len() - 1], prec, None, Some(0.0))
        .sphlab_text(format!("{text}{after}"))
        .check(falls(values), criterion)
}

/// The tangential form's rows with the same measures from its lattice runs under the rule's
/// α × 0.5 and × 2 (`runs/nx<nx>-tangential-alpha{1,4}`, and for the band maximum the traceless
/// form's `runs/nx<nx>-alpha{1,4}` beside them), judged by each row's own criterion.
fn tangential_bands(root: &Path, rep: &mut CaseReport) {
    let nxs = crate::validate::convergence::TANGENTIAL_NX;
    let on = "p_b and c0 by the capillary rule at each nx (α = 2, ε = 0.01; docs/PHYSICS.md §3.1), μ = 0.05, Mode B, \
              no-slip, the lattice start, the tangential form's runs beside the traceless form's";
    // The row's own three values, one per nx ("a → b → c" or "a, b, c").
    let values = |prefix: &str| -> Option<Vec<f64>> {
        let r = rep.rows.iter().find(|r| r.quantity.starts_with(prefix))?;
        let v: Vec<f64> = r.sphlab.split([',', '→']).filter_map(|p| p.trim().parse().ok()).collect();
        (v.len() == nxs.len()).then_some(v)
    };
    let dens = values("tangential form: max |ρ/ρ0 − 1| for t ≥ 1 with refinement")
        .and_then(|v| sensitivity::lattice_alpha_band(root, "-tangential", &nxs, &v, true, falls));
    let within = |t: &[f64]| t.iter().all(|v| *v < ANGLE_TOL_DEG);
    let theta = values("tangential form: |θ − 60°| at nx")
        .and_then(|v| sensitivity::lattice_alpha_band(root, "-tangential", &nxs, &v, false, within));
    // The band-maximum row's resolutions from its own text ("nx 33: a vs b; nx 45: …").
    let band_max =
        rep.rows.iter().find(|r| r.quantity.starts_with("tangential form: last state's band max")).and_then(|r| {
            let nxs: Vec<u32> = r
                .sphlab
                .split(';')
                .filter_map(|p| p.trim().strip_prefix("nx ")?.split(':').next()?.parse().ok())
                .collect();
            sensitivity::band_max_alpha_band(root, &nxs, r.value)
        });
    qualify_each(
        rep,
        "tangential form: ",
        on,
        &[("|ρ/ρ0 − 1|", &dens), ("|θ − 60°|", &theta), ("band max", &band_max)],
    );
}

/// Qualifies every row whose quantity contains `rows` with `on` and the band of the first of
/// `bands` whose key its quantity contains (none where no key does; the key "" takes any row).
fn qualify_each(rep: &mut CaseReport, rows: &str, on: &str, bands: &[(&str, &Option<Band>)]) {
    for r in rep.rows.iter_mut().filter(|r| r.quantity.contains(rows)) {
        let band = bands.iter().find(|(key, _)| r.quantity.contains(key)).and_then(|(_, b)| b.as_ref());
        r.qualify(on, band);
    }
}

/// Where the last states' density error sits, from the convergence case's band rows
/// (`convergence::band_density`): "; last state, max in the band / outside: …" or nothing.
fn band_note(rep: &CaseReport) -> String {
    let parts: Vec<String> = rep
        .rows
        .iter()
        .filter(|r| r.quantity.contains("|ρ/ρ0 − 1| of the last state"))
        .filter_map(|r| {
            let who = r.quantity.split(':').next()?;
            let mut v = r.sphlab.split(" / ");
            Some(format!("{who} {} / {}", v.next()?, v.next()?))
        })
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!("; the last state's max in the interface band / outside it: {}", parts.join("; "))
    }
}

/// Max |ρ/ρ0 − 1| for t ≥ 1 of the committed `convergence/runs/nx<nx>` series (NaN without
/// one), for a report written before the case had a row for it.
fn max_density_error(root: &Path, nx: u32) -> f64 {
    read_series(&root.join(format!("convergence/runs/nx{nx}")))
        .iter()
        .filter(|r| r.t >= 1.0)
        .map(|r| r.max_density_error)
        .fold(f64::NAN, f64::max)
}

/// θ (circle fit, mean over [4.3, 4.5]) of the committed nx run at p_b = 45 held fixed
/// (`convergence/pb-check/runs/nx<nx>-pb45`), when there is one.
fn fixed_pb_angle(root: &Path, nx: u32) -> Option<f64> {
    end_angle(&root.join(format!("convergence/pb-check/runs/nx{nx}-pb45")))
}
