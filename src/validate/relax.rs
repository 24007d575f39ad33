//! Case `relax-60` (docs/PHYSICS.md §9(c), thesis §4.2.3, Figs. 4.10–4.15): the 90° drop relaxing
//! to 60°, Mode B and Mode A, no-slip and free-slip bottom walls, and both no-slip modes again
//! from a 45° cap, so that each mode's end angle is approached from both sides (equilibrium or
//! pinning). Contact angle vs time (three methods), D/D0 vs time against the analytic
//! equilibrium cap (1.385), shear profiles near t = 0.25 and at the end.

use super::data::{col, Row as SRow};
use super::report::CaseReport;
use super::{Ctx, ValidateError};
use crate::diagnostics::equilibrium_cap;

mod case;
mod compare;
#[cfg(test)]
mod tests;

/// Initial drop radius of `relax-60`.
pub(super) const R0: f64 = 0.25;

/// The analytic equilibrium D/D0 of the R = 0.25 half-drop at 60°, at the wall.
pub fn analytic_spread() -> f64 {
    analytic_spread_at(0.0)
}

/// The analytic 60° cap's D/D0 at height `y` above the wall: the series' `spread_factor` is
/// measured at the first row's height Δx/2 (`diagnostics::contact_half_width`), where the cap is
/// (Δx/2)·cot 60° narrower than at the wall.
pub fn analytic_spread_at(y: f64) -> f64 {
    let cap = equilibrium_cap(std::f64::consts::PI * R0 * R0 / 2.0, 60f64.to_radians());
    (cap.radius * cap.radius - (y - cap.centre_y).powi(2)).max(0.0).sqrt() / R0
}

/// D/D0 at the wall, per series row: the first-row D/D0 carried down the Δx/2 to the wall
/// along the row's circle-fit angle, D/D0 + (Δx/2)·cot θ / R (rows with both values only).
pub fn wall_spread(rows: &[SRow], dx: f64) -> Vec<(f64, f64)> {
    col(rows, |r| match (r.spread_factor, r.theta_circle_fit) {
        (Some(d), Some(th)) if th > 0.0 && th < 180.0 => Some(d + 0.5 * dx / (R0 * th.to_radians().tan())),
        _ => None,
    })
}

/// Thesis Fig. 4.13: D/D0 stays within [1, 1.4].
pub const THESIS_SPREAD_MAX: f64 = 1.4;

/// A relax-60 run of the case: its id (the run directory), its label in the report, its scene
/// overrides, and the angle at which its drop starts on the wall.
pub struct Variant {
    /// Run id.
    pub id: &'static str,
    /// Label in rows, notes and plots.
    pub label: &'static str,
    /// Scene overrides beyond the case's common ones (`KEY=VALUE`).
    pub sets: Vec<String>,
    /// Initial contact angle (deg): 90 is the scene's half-disc, anything else the cap of the same
    /// area ([`start_sets`]).
    pub start_deg: f64,
    /// For a start other than 90°: the id of the same variant started at 90°, whose end angle
    /// this one approaches from the other side.
    pub from_90: Option<&'static str>,
}

impl Variant {
    /// Mode B, the thesis's method, and Mode A with the unbalanced Young force (docs/PHYSICS.md
    /// §8.2.5), whose equilibria are held to 60° (Mode A's wall bands are not held to it:
    /// relax-60/mode-a-check/README.md). Read from the variant's scene (relax-60 with its
    /// overrides), as the run itself sees it.
    pub fn held_to_young(&self) -> bool {
        use crate::scene::{ContactMode, WallTension};
        crate::scene::overrides::apply_overrides(&crate::scene::builtin::relax_60(), &self.sets)
            .is_ok_and(|s| s.contact.mode == ContactMode::B || s.contact.wall_tension == WallTension::Unbalanced)
    }
}

/// The run of Mode A with the unbalanced Young force, no-slip, from 90°.
const YOUNG_NOSLIP: &str = "a-young-noslip";

/// The angle the second start comes from: below 60°, so that the contact line recedes to its
/// equilibrium while the 90° start advances to it.
pub const START_BELOW_DEG: f64 = 45.0;

/// The initial cap of the half-disc's area meeting the wall at `theta_deg` (analytic_flows'
/// `equilibrium_cap`, centred on the symmetry line below the wall).
pub(super) fn start_cap(theta_deg: f64) -> crate::diagnostics::Cap {
    equilibrium_cap(std::f64::consts::PI * R0 * R0 / 2.0, theta_deg.to_radians())
}

/// Overrides that start the drop at `theta_deg` instead of 90°: the circle of the equal-area cap
/// (none at 90°). `examples/analysis/relax_start_angle.sh` writes the same scene for any nx and mode.
pub fn start_sets(theta_deg: f64) -> Vec<String> {
    if theta_deg == 90.0 {
        return Vec::new();
    }
    let cap = start_cap(theta_deg);
    vec![format!("shapes.0.centre=[0.0,{}]", cap.centre_y), format!("shapes.0.radius={}", cap.radius)]
}

/// The variants: the thesis's four; Mode B no-slip with the transport-velocity formulation at
/// p_b = ρ0c0² (Adami, Hu & Adams 2013; CPU only); both modes, no-slip, started below 60°
/// ([`START_BELOW_DEG`]), so that each mode's end angle is approached from both sides; and Mode
/// A with the unbalanced Young force in place of the wall bands (docs/PHYSICS.md §8.2.5), both
/// walls and both starts.
pub fn variants() -> Vec<Variant> {
    let ph = &crate::scene::builtin::relax_60().phases[0];
    let p_b = crate::scene::builtin::transport_background_pressure(ph.rho0, ph.c0);
    let v = |id, label, sets: Vec<String>, start_deg| Variant { id, label, sets, start_deg, from_90: None };
    let below = |id, label, sets, from_90| Variant { from_90: Some(from_90), ..v(id, label, sets, START_BELOW_DEG) };
    let mode_a = || vec!["contact.mode=a".to_string()];
    let young = || vec!["contact.mode=a".to_string(), "contact.wall_tension=unbalanced".to_string()];
    let free = || vec!["domain.bottom=free-slip".to_string()];
    vec![
        v("b-noslip", "Mode B, no-slip", vec![], 90.0),
        v(
            "b-noslip-tvf",
            "Mode B, no-slip, transport velocity",
            vec!["time.background=\"transport\"".into(), format!("phases.0.p_b={p_b}"), format!("phases.1.p_b={p_b}")],
            90.0,
        ),
        v("b-freeslip", "Mode B, free-slip", vec!["domain.bottom=free-slip".into()], 90.0),
        v("a-noslip", "Mode A, no-slip", mode_a(), 90.0),
        v("a-freeslip", "Mode A, free-slip", [mode_a(), vec!["domain.bottom=free-slip".into()]].concat(), 90.0),
        below("b-noslip-from45", "Mode B, no-slip, from 45°", start_sets(START_BELOW_DEG), "b-noslip"),
        below(
            "a-noslip-from45",
            "Mode A, no-slip, from 45°",
            [mode_a(), start_sets(START_BELOW_DEG)].concat(),
            "a-noslip",
        ),
        v(YOUNG_NOSLIP, "Mode A, unbalanced Young force, no-slip", young(), 90.0),
        v("a-young-freeslip", "Mode A, unbalanced Young force, free-slip", [young(), free()].concat(), 90.0),
        below(
            "a-young-noslip-from45",
            "Mode A, unbalanced Young force, no-slip, from 45°",
            [young(), start_sets(START_BELOW_DEG)].concat(),
            YOUNG_NOSLIP,
        ),
    ]
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    super::executor::execute(ctx, &mut case::Relax::new(ctx))
}
