//! The equal-density capillary wave's resolution study (case `capillary-wave`, full size only):
//! both viscous forms at Δx = λ/32, λ/44 (the case's own runs), λ/64 and λ/88 under the
//! capillary rule at each Δx, three realisations at λ/44 from a jittered lattice, and the
//! transport-velocity and tangential stress forms beside the rule's runs. Judged as
//! stated before the runs (reports/validation/capillary-wave/README.md): the three-period rms
//! and the period error fall at every refinement, the rms is within the case's bound at the two
//! finest, and the realisations' scatter is smaller than the change from λ/44 to λ/64.

use super::case::CaseRun;
use super::report::Row;
use super::richardson::extrapolate;
use super::scatter::{self, stats, JITTER, SEEDS};
use super::RunSpec;

/// The resolutions beside the scene's own λ/44 (which the case's `ratio1` runs cover).
pub const EXTRA_NX: [u32; 3] = [32, 64, 88];
/// The resolutions of the transport-velocity runs (p_b out of the momentum equation).
pub const TRANSPORT_NX: [u32; 2] = [44, 88];
/// Id suffix of the transport-velocity runs.
pub const TRANSPORT: &str = "-tvf";
/// Stated before the transport runs: at λ/88 the period within this of Prosperetti's …
const TRANSPORT_PERIOD_TOL: f64 = 0.015;
/// … and the damping rate within this.
const TRANSPORT_DAMPING_TOL: f64 = 0.10;
/// The resolutions of the tangential-form runs (`surface_tension.tensor = "tangential"`).
pub const TANGENTIAL_NX: [u32; 2] = [44, 64];
/// Id suffix of the tangential-form runs.
pub const TANGENTIAL: &str = "-tangential";
/// Stated before the tangential runs: at each Δx the rms within this of the traceless form's …
const TANGENTIAL_RMS_TOL: f64 = 0.01;
/// … and the period error within this.
const TANGENTIAL_PERIOD_TOL: f64 = 0.01;
/// The tangential form's run at a lower p_b: its resolution and factor on the rule's p_b.
pub const TANGENTIAL_LOW_PB: (u32, f64) = (64, 0.5);
/// Stated before that run: its damping rate within this of Prosperetti's (and its rms within
/// the case's bound).
const TANGENTIAL_LOW_PB_DAMPING_TOL: f64 = 0.15;
/// The resolution of the p_b sweep, and its factors on the rule's p_b (× 1 is `ratio1-nx64`).
pub const PB_NX: u32 = 64;
pub const PB_FACTORS: [f64; 3] = [0.75, 1.5, 2.0];
/// Stated before the p_b sweep: the least span of its period errors for p_b to count as moving
/// the period.
const PB_SPAN: f64 = 0.01;

/// The id of the p_b sweep's run at factor `f`.
fn pb_id(f: f64) -> String {
    format!("ratio1-nx{PB_NX}-pb{f}")
}

/// The finer resolutions at which the rms must meet the case's bound.
const FINE_NX: [u32; 2] = [64, 88];

/// The scene's own resolution (the `ratio1` runs').
fn base_nx() -> u32 {
    crate::scene::builtin::builtin("capillary-wave").map_or(44, |s| s.domain.nx)
}

/// The id of the equal-density run at `nx` with the form's id suffix (`""` or `-projected`).
pub fn id_at(nx: u32, suffix: &str) -> String {
    if nx == base_nx() {
        format!("ratio1{suffix}")
    } else {
        format!("ratio1-nx{nx}{suffix}")
    }
}

/// The study's runs: each extra resolution with both forms, then the realisations.
pub fn runs() -> Vec<CaseRun> {
    let mut runs = Vec::new();
    for nx in EXTRA_NX {
        for (suffix, form, name) in [("", None, "T70"), ("-projected", Some("viscous_form=projected"), "projected")] {
            let mut sets = vec![format!("domain.nx={nx}")];
            sets.extend(form.map(String::from));
            let label = format!("density ratio 1, {name} viscous form, Δx = λ/{nx}");
            runs.push(CaseRun::new(RunSpec::new(id_at(nx, suffix), "capillary-wave", &sets, None, 0), &label));
        }
    }
    for nx in TRANSPORT_NX {
        let mut sets = vec!["time.background=transport".to_string()];
        if nx != base_nx() {
            sets.push(format!("domain.nx={nx}"));
        }
        let label =
            format!("density ratio 1, T70, transport-velocity form (p_b out of the momentum equation), Δx = λ/{nx}");
        runs.push(CaseRun::new(
            RunSpec::new(format!("{}{TRANSPORT}", id_at(nx, "")), "capillary-wave", &sets, None, 0),
            &label,
        ));
    }
    for nx in TANGENTIAL_NX {
        let mut sets = vec!["surface_tension.tensor=tangential".to_string()];
        if nx != base_nx() {
            sets.push(format!("domain.nx={nx}"));
        }
        let label = format!("density ratio 1, T70, tangential stress form (docs/PHYSICS.md §5.3), Δx = λ/{nx}");
        runs.push(CaseRun::new(
            RunSpec::new(format!("{}{TANGENTIAL}", id_at(nx, "")), "capillary-wave", &sets, None, 0),
            &label,
        ));
    }
    let (nx, f) = TANGENTIAL_LOW_PB;
    let mut sets = super::capillary_wave::sets("capillary-wave", nx, f);
    sets.push("surface_tension.tensor=tangential".into());
    let label = format!("density ratio 1, T70, tangential stress form, Δx = λ/{nx}, p_b × {f}");
    runs.push(CaseRun::new(RunSpec::new(tangential_low_pb_id(), "capillary-wave", &sets, None, 0), &label));
    for f in PB_FACTORS {
        let label = format!("density ratio 1, T70, Δx = λ/{PB_NX}, p_b × {f}");
        let sets = super::capillary_wave::sets("capillary-wave", PB_NX, f);
        runs.push(CaseRun::new(RunSpec::new(pb_id(f), "capillary-wave", &sets, None, 0), &label));
    }
    for seed in SEEDS {
        let sets = scatter::sets(seed);
        let label = format!("density ratio 1, T70, Δx = λ/{}, lattice jittered by {JITTER}Δx, seed {seed}", base_nx());
        runs.push(CaseRun::new(
            RunSpec::new(format!("ratio1{}", scatter::suffix(seed)), "capillary-wave", &sets, None, 0),
            &label,
        ));
    }
    runs
}

/// The study's rows from each run's three-period rms, (period, Prosperetti's period by the
/// same fit) and (damping rate, Prosperetti's by the same fit); rows whose runs are missing are
/// left out.
pub fn rows(rms: &[(String, f64)], periods: &[(String, f64, f64)], damping: &[(String, f64, f64)]) -> Vec<Row> {
    let get_rms = |id: &str| rms.iter().find(|r| r.0 == id).map(|r| r.1);
    let get_err = |id: &str| periods.iter().find(|p| p.0 == id).map(|p| p.1 / p.2 - 1.0);
    let mut all_nx: Vec<u32> = EXTRA_NX.into_iter().chain([base_nx()]).collect();
    all_nx.sort_unstable();
    let mut out = Vec::new();
    for (suffix, name) in [("", "T70"), ("-projected", "projected")] {
        let ids: Vec<String> = all_nx.iter().map(|&nx| id_at(nx, suffix)).collect();
        let lambdas = all_nx.iter().map(|nx| format!("λ/{nx}")).collect::<Vec<_>>().join(", ");
        if let Some(r) = ids.iter().map(|id| get_rms(id)).collect::<Option<Vec<f64>>>() {
            let falls = r.windows(2).all(|w| w[1] < w[0]);
            let fine_ok = all_nx
                .iter()
                .zip(&r)
                .filter(|(nx, _)| FINE_NX.contains(nx))
                .all(|(_, v)| *v <= super::capillary_wave::RMS_TOL);
            let text = r.iter().map(|v| format!("{v:.4}")).collect::<Vec<_>>().join(" → ");
            let last = *r.last().unwrap_or(&f64::NAN);
            out.push(
                Row::new(&format!("rms of a/a0 − Prosperetti over 3 periods at Δx = {lambdas}, density ratio 1, {name}"), last, 4, None, Some(0.0))
                    .sphlab_text(text)
                    .check(
                        falls && fine_ok,
                        &format!(
                            "falls at every refinement and ≤ {} at λ/64 and λ/88, stated before the runs (README.md); \
                             p_b and c0 by the capillary rule at each Δx (α = 2, ε = 0.01; docs/PHYSICS.md §3.1), La = 3000, \
                             the quintic at h = 1.2Δx, the lattice start",
                            super::capillary_wave::RMS_TOL
                        ),
                    ),
            );
        }
        if let Some(e) = ids.iter().map(|id| get_err(id)).collect::<Option<Vec<f64>>>() {
            let falls = e.windows(2).all(|w| w[1].abs() < w[0].abs());
            let n = e.len();
            let h3 = [all_nx[n - 3], all_nx[n - 2], all_nx[n - 1]].map(|nx| 1.0 / nx as f64);
            let rich = extrapolate(h3, [e[n - 3], e[n - 2], e[n - 1]]);
            let text = e.iter().map(|v| format!("{:+.2} %", 100.0 * v)).collect::<Vec<_>>().join(" → ");
            out.push(
                Row::new(
                    &format!(
                        "period error against Prosperetti's (same fit) at Δx = {lambdas}, density ratio 1, {name}"
                    ),
                    *e.last().unwrap_or(&f64::NAN),
                    4,
                    None,
                    Some(0.0),
                )
                .sphlab_text(format!("{text} (Richardson on the three finest, relative error: {rich})"))
                .check(falls, "|error| falls at every refinement, stated before the runs (README.md)"),
            );
        }
    }
    out.extend(transport_rows(rms, periods, damping));
    out.extend(tangential_rows(rms, periods, damping));
    out.extend(tangential_low_pb_row(rms, periods, damping));
    out.extend(pb_row(periods));
    let seeds: Option<Vec<f64>> = SEEDS.iter().map(|s| get_rms(&format!("ratio1{}", scatter::suffix(*s)))).collect();
    // T70's change from the scene's Δx to the next finer one, which the realisations' scatter is
    // set against (the two runs alone: the study's other resolutions need not have run).
    let next_nx = all_nx.iter().copied().find(|&nx| nx > base_nx());
    let change = next_nx.and_then(|nx| Some((get_rms(&id_at(base_nx(), ""))? - get_rms(&id_at(nx, ""))?).abs()));
    if let (Some(seeds), Some(change)) = (seeds, change) {
        let (mean, sd, _) = stats(&seeds);
        let text = format!(
            "{} (mean {mean:.4}, sd {sd:.4}; lattice {}); T70's change λ/{} → λ/64: {change:.4}",
            seeds.iter().map(|v| format!("{v:.4}")).collect::<Vec<_>>().join(", "),
            get_rms("ratio1").map_or("not run".into(), |v| format!("{v:.4}")),
            base_nx()
        );
        out.push(
            Row::new(
                &format!("rms over 3 periods from starts jittered by {JITTER}Δx (seeds 1–3), density ratio 1, T70, Δx = λ/{}", base_nx()),
                sd,
                4,
                None,
                None,
            )
            .sphlab_text(text)
            .check(sd < change, "sd of the realisations below the rms's change from λ/44 to λ/64, stated before the runs (README.md)"),
        );
    }
    out
}

/// The p_b sweep at λ/64: the period error at each factor, judged as stated (monotone falling
/// with p_b, spanning at least [`PB_SPAN`]).
fn pb_row(periods: &[(String, f64, f64)]) -> Option<Row> {
    let err = |id: &str| periods.iter().find(|p| p.0 == id).map(|p| p.1 / p.2 - 1.0);
    let mut pts: Vec<(f64, f64)> = PB_FACTORS.iter().map(|&f| Some((f, err(&pb_id(f))?))).collect::<Option<_>>()?;
    pts.push((1.0, err(&id_at(PB_NX, ""))?));
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let falls = pts.windows(2).all(|w| w[1].1 < w[0].1);
    let (lo, hi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p.1), h.max(p.1)));
    let text = pts.iter().map(|(f, e)| format!("× {f}: {:+.2} %", 100.0 * e)).collect::<Vec<_>>().join(", ");
    Some(
        Row::new(
            &format!("period error against p_b (× the rule's), density ratio 1, T70, Δx = λ/{PB_NX}"),
            hi - lo,
            4,
            None,
            None,
        )
        .sphlab_text(format!("{text} (span {:.2} points)", 100.0 * (hi - lo)))
        .check(
            falls && hi - lo >= PB_SPAN,
            &format!(
                "falls with p_b at every step and spans ≥ {:.0} point, stated before the runs (README.md): p_b in the \
                     momentum equation moves the period",
                100.0 * PB_SPAN
            ),
        ),
    )
}

/// One form's run against the rule's at Δx = λ/`nx`: (rms, period error, damping error) of the
/// rule's run and of the form's (id suffix `suffix`), and the info row that lists them; None
/// while either run is missing.
fn form_pair(
    nx: u32,
    suffix: &str,
    what: &str,
    rms: &[(String, f64)],
    periods: &[(String, f64, f64)],
    damping: &[(String, f64, f64)],
) -> Option<(Row, [f64; 3], [f64; 3])> {
    let rel = |v: &[(String, f64, f64)], id: &str| v.iter().find(|p| p.0 == id).map(|p| p.1 / p.2 - 1.0);
    let get_rms = |id: &str| rms.iter().find(|r| r.0 == id).map(|r| r.1);
    let (rule, form) = (id_at(nx, ""), format!("{}{suffix}", id_at(nx, "")));
    let a = [get_rms(&rule)?, rel(periods, &rule)?, rel(damping, &rule)?];
    let b = [get_rms(&form)?, rel(periods, &form)?, rel(damping, &form)?];
    let row = Row::new(
        &format!(
            "density ratio 1, T70, Δx = λ/{nx}: rms over 3 periods, period error, damping error (same fit): {what}"
        ),
        b[1],
        4,
        None,
        Some(0.0),
    )
    .sphlab_text(format!(
        "rms {:.4} → {:.4}; period {:+.2} % → {:+.2} %; damping {:+.1} % → {:+.1} %",
        a[0],
        b[0],
        100.0 * a[1],
        100.0 * b[1],
        100.0 * a[2],
        100.0 * b[2]
    ));
    Some((row, a, b))
}

/// The tangential-form runs against the traceless form's at the same Δx, each with the verdict
/// stated before the runs.
fn tangential_rows(rms: &[(String, f64)], periods: &[(String, f64, f64)], damping: &[(String, f64, f64)]) -> Vec<Row> {
    let what = "the traceless Hu–Adams tensor → the tangential form (docs/PHYSICS.md §5.3)";
    let mut out = Vec::new();
    for nx in TANGENTIAL_NX {
        let Some((row, a, b)) = form_pair(nx, TANGENTIAL, what, rms, periods, damping) else { continue };
        out.push(row.check(
            (b[0] - a[0]).abs() <= TANGENTIAL_RMS_TOL && (b[1] - a[1]).abs() <= TANGENTIAL_PERIOD_TOL,
            &format!(
                "rms within {TANGENTIAL_RMS_TOL} and period error within {:.0} point of the traceless form's, stated before \
                 the runs (../tangential-stress/README.md): the same total stress and the same p_b",
                100.0 * TANGENTIAL_PERIOD_TOL
            ),
        ));
    }
    out
}

/// The id of the tangential form's run at a lower p_b.
fn tangential_low_pb_id() -> String {
    let (nx, f) = TANGENTIAL_LOW_PB;
    format!("{}{TANGENTIAL}-pb{f}", id_at(nx, ""))
}

/// The tangential form at the lower p_b against the traceless form at the rule's, with the
/// verdict stated before the run.
fn tangential_low_pb_row(
    rms: &[(String, f64)],
    periods: &[(String, f64, f64)],
    damping: &[(String, f64, f64)],
) -> Option<Row> {
    let (nx, f) = TANGENTIAL_LOW_PB;
    let suffix = tangential_low_pb_id().trim_start_matches(&id_at(nx, "")).to_string();
    let what = format!("the traceless form at the rule's p_b → the tangential form at p_b × {f}");
    let (row, _, b) = form_pair(nx, &suffix, &what, rms, periods, damping)?;
    Some(row.check(
        b[0] <= super::capillary_wave::RMS_TOL && b[2].abs() <= TANGENTIAL_LOW_PB_DAMPING_TOL,
        &format!(
            "rms ≤ {} and damping within {:.0} % of Prosperetti's, stated before the run (../tangential-stress/README.md): \
             the band's pressure back at the traceless form's",
            super::capillary_wave::RMS_TOL,
            100.0 * TANGENTIAL_LOW_PB_DAMPING_TOL
        ),
    ))
}

/// The transport-velocity runs against the rule's at the same Δx: rms, period and damping
/// errors; at the finest, the verdict stated before the runs.
fn transport_rows(rms: &[(String, f64)], periods: &[(String, f64, f64)], damping: &[(String, f64, f64)]) -> Vec<Row> {
    let what = "p_b by the rule in the momentum equation → transport-velocity form";
    let mut out = Vec::new();
    for nx in TRANSPORT_NX {
        let Some((row, _, b)) = form_pair(nx, TRANSPORT, what, rms, periods, damping) else { continue };
        let (pt, dt) = (b[1], b[2]);
        out.push(if nx == *TRANSPORT_NX.iter().max().unwrap_or(&nx) {
            row.check(
                pt.abs() <= TRANSPORT_PERIOD_TOL && dt.abs() <= TRANSPORT_DAMPING_TOL,
                &format!(
                    "the transport form's period within {:.1} % and damping within {:.0} % of Prosperetti's at the finest Δx, \
                     stated before the runs (README.md): p_b acting on the kernel-sum error moves the fine runs off",
                    100.0 * TRANSPORT_PERIOD_TOL,
                    100.0 * TRANSPORT_DAMPING_TOL
                ),
            )
        } else {
            row
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study(rms: [f64; 4], periods: [f64; 4]) -> Vec<Row> {
        let nx = [32, 44, 64, 88];
        let mut r: Vec<(String, f64)> = nx.iter().zip(rms).map(|(&n, v)| (id_at(n, ""), v)).collect();
        r.extend(nx.iter().zip(rms).map(|(&n, v)| (id_at(n, "-projected"), v)));
        r.extend(SEEDS.iter().map(|s| (format!("ratio1{}", scatter::suffix(*s)), 0.05 + 0.001 * *s as f64)));
        let p: Vec<(String, f64, f64)> = nx.iter().zip(periods).map(|(&n, v)| (id_at(n, ""), v, 1.0)).collect();
        rows(&r, &p, &[])
    }

    #[test]
    fn falling_errors_pass_and_a_rise_fails() {
        let rows = study([0.08, 0.05, 0.03, 0.02], [1.05, 1.026, 1.012, 1.006]);
        assert_eq!(rows.len(), 4, "T70 rms and period, projected rms, realisations");
        assert!(rows.iter().all(|r| r.verdict.starts_with("pass")), "{rows:#?}");
        let rose = study([0.08, 0.05, 0.06, 0.02], [1.05, 1.026, 1.03, 1.006]);
        assert!(rose[0].verdict.starts_with("FAIL") && rose[1].verdict.starts_with("FAIL"), "{rose:#?}");
        let coarse = study([0.09, 0.08, 0.06, 0.055], [1.05, 1.026, 1.012, 1.006]);
        assert!(coarse[0].verdict.starts_with("FAIL"), "λ/88 above the bound: {coarse:#?}");
    }

    #[test]
    fn the_transport_row_judges_the_finest_resolution_only() {
        let ids = ["ratio1", "ratio1-tvf", "ratio1-nx88", "ratio1-nx88-tvf"];
        let rms: Vec<(String, f64)> = ids.iter().map(|i| (i.to_string(), 0.05)).collect();
        let fit = |v: [f64; 4]| -> Vec<(String, f64, f64)> {
            ids.iter().zip(v).map(|(i, x)| (i.to_string(), x, 1.0)).collect()
        };
        let good = transport_rows(&rms, &fit([1.026, 1.01, 0.97, 1.01]), &fit([0.97, 0.95, 1.19, 1.05]));
        assert_eq!(good.len(), 2);
        assert_eq!(good[0].verdict, "info", "λ/44 carries no verdict: {good:#?}");
        assert!(good[1].verdict.starts_with("pass"), "{good:#?}");
        let off = transport_rows(&rms, &fit([1.026, 1.01, 0.97, 0.975]), &fit([0.97, 0.95, 1.19, 1.05]));
        assert!(off[1].verdict.starts_with("FAIL"), "period −2.5 %: {off:#?}");
        let damped = transport_rows(&rms, &fit([1.026, 1.01, 0.97, 1.01]), &fit([0.97, 0.95, 1.19, 1.15]));
        assert!(damped[1].verdict.starts_with("FAIL"), "damping +15 %: {damped:#?}");
    }

    #[test]
    fn the_tangential_rows_judge_against_the_traceless_runs() {
        let ids = ["ratio1", "ratio1-tangential", "ratio1-nx64", "ratio1-nx64-tangential"];
        let pairs =
            |v: [f64; 4]| -> Vec<(String, f64)> { ids.iter().zip(v).map(|(i, x)| (i.to_string(), x)).collect() };
        let fit = |v: [f64; 4]| -> Vec<(String, f64, f64)> {
            ids.iter().zip(v).map(|(i, x)| (i.to_string(), x, 1.0)).collect()
        };
        let damping = fit([0.97, 0.98, 0.9, 0.95]);
        let close = tangential_rows(&pairs([0.053, 0.057, 0.038, 0.033]), &fit([1.026, 1.02, 0.983, 0.99]), &damping);
        assert_eq!(close.len(), 2);
        assert!(close.iter().all(|r| r.verdict.starts_with("pass")), "{close:#?}");
        let moved = tangential_rows(&pairs([0.053, 0.07, 0.038, 0.033]), &fit([1.026, 1.02, 0.983, 1.0]), &damping);
        assert!(moved[0].verdict.starts_with("FAIL") && moved[1].verdict.starts_with("FAIL"), "{moved:#?}");
        assert!(tangential_rows(&pairs([0.053, 0.057, 0.038, 0.033]), &fit([1.0; 4])[..2], &damping).len() == 1);
        let ids = ["ratio1-nx64", "ratio1-nx64-tangential-pb0.5"];
        let two =
            |a: f64, b: f64| -> Vec<(String, f64, f64)> { vec![(ids[0].into(), a, 1.0), (ids[1].into(), b, 1.0)] };
        let rms = |v: f64| vec![(ids[0].to_string(), 0.038), (ids[1].to_string(), v)];
        let low = |r: f64, d: f64| tangential_low_pb_row(&rms(r), &two(0.983, 0.99), &two(0.89, d)).unwrap().verdict;
        assert!(low(0.04, 1.1).starts_with("pass"), "{}", low(0.04, 1.1));
        assert!(low(0.06, 1.1).starts_with("FAIL") && low(0.04, 1.2).starts_with("FAIL"));
    }

    #[test]
    fn the_pb_sweep_passes_only_monotone_and_wide() {
        let fit = |v: [f64; 4]| -> Vec<(String, f64, f64)> {
            let ids = [pb_id(0.75), id_at(PB_NX, ""), pb_id(1.5), pb_id(2.0)];
            ids.into_iter().zip(v).map(|(i, x)| (i, x, 1.0)).collect()
        };
        assert!(pb_row(&fit([1.0, 0.985, 0.975, 0.965])).unwrap().verdict.starts_with("pass"));
        assert!(pb_row(&fit([1.0, 0.985, 0.99, 0.965])).unwrap().verdict.starts_with("FAIL"), "not monotone");
        assert!(pb_row(&fit([0.99, 0.988, 0.985, 0.984])).unwrap().verdict.starts_with("FAIL"), "span 0.6 point");
        assert!(pb_row(&fit([1.0, 0.985, 0.975, 0.965])[..3]).is_none(), "a factor missing");
    }

    #[test]
    fn scatter_larger_than_the_change_fails() {
        let rows = study([0.08, 0.05, 0.0495, 0.049], [1.05, 1.026, 1.012, 1.006]);
        let real = rows.iter().find(|r| r.quantity.starts_with("rms over 3 periods from starts jittered")).unwrap();
        assert!(real.verdict.starts_with("FAIL"), "{real:#?}");
    }
}
