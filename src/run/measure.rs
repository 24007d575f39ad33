//! The series row of `sphlab run` (`series.csv`, read back by `validate`): what is measured on
//! a frame (energy, centroid, masses, density error, speed and where their maxima sit, the
//! binding dt limit, contact angles and spread, the interface wave's amplitude).

use crate::backend::Frame;
use crate::diagnostics::{contact_angle, flow};
use crate::fallible::AllocError;
use crate::scene::{ContactMode, Scene, ShapeKind, Side};
use serde::Serialize;

/// One row of `series.csv` (read back by `validate`).
#[derive(Clone, Debug, Serialize, serde::Deserialize, Default)]
pub struct SeriesRow {
    /// Time.
    pub t: f64,
    /// Step.
    pub step: u64,
    /// Last dt.
    pub dt: f64,
    /// Kinetic energy of the liquid (phase 0).
    pub kinetic_energy: f64,
    /// Liquid centroid x.
    pub centroid_x: f64,
    /// Liquid centroid y.
    pub centroid_y: f64,
    /// Total mass of phase 0.
    pub mass_phase0: f64,
    /// Total mass of phase 1 (0 if absent).
    pub mass_phase1: f64,
    /// max |ρ/ρ0 − 1| over fluid particles.
    pub max_density_error: f64,
    /// Max fluid speed.
    pub max_speed: f64,
    /// The limit that binds at this row's state (`cfl`, `viscous`, `force`, `capillary`): the one
    /// that sets an automatic dt; `fixed` when the scene's dt is fixed.
    #[serde(default)]
    pub dt_limit: String,
    /// dt over the tightest limit at this row's state (≈ 1 for an automatic dt; above 1: a
    /// fixed dt past a limit).
    #[serde(default)]
    pub dt_over_limit: f64,
    /// Contact angle, two-point method (degrees; empty when not measurable).
    pub theta_two_point: Option<f64>,
    /// Contact angle, circle fit.
    pub theta_circle_fit: Option<f64>,
    /// Contact angle, area inversion.
    pub theta_area: Option<f64>,
    /// Contact half-width x_tp.
    pub x_tp: Option<f64>,
    /// Spread factor D/D0.
    pub spread_factor: Option<f64>,
    /// Interface wave amplitude a (scenes with `[interface_wave]`; `diagnostics::wave`).
    #[serde(default)]
    pub wave_amplitude: Option<f64>,
    /// Position x of the fluid particle with the largest |ρ/ρ0 − 1| (`max_density_error`).
    #[serde(default)]
    pub max_density_error_x: Option<f64>,
    /// Position y of that particle.
    #[serde(default)]
    pub max_density_error_y: Option<f64>,
    /// Position x of the fastest fluid particle (`max_speed`).
    #[serde(default)]
    pub max_speed_x: Option<f64>,
    /// Position y of that particle.
    #[serde(default)]
    pub max_speed_y: Option<f64>,
}

/// Measures one series row from a frame (the circle fit empty where its buffers cannot be
/// allocated; [`try_measure`] says so).
pub fn measure(scene: &Scene, fr: &Frame) -> SeriesRow {
    let angles = |pos: &[[f64; 2]], phase: &[u32], dx, y_w, mirrored| {
        Ok::<_, std::convert::Infallible>(contact_angle::measure_all(pos, phase, dx, y_w, mirrored))
    };
    match measure_with(scene, fr, angles) {
        Ok(row) => row,
        Err(never) => match never {},
    }
}

/// [`measure`], or the allocation of the contact-angle diagnostic that failed (its buffers are
/// at most [`contact_angle::max_bytes`] of the fluid particles).
pub fn try_measure(scene: &Scene, fr: &Frame) -> Result<SeriesRow, AllocError> {
    measure_with(scene, fr, contact_angle::try_measure_all)
}

/// One series row, the contact angles from `angles`.
fn measure_with<E>(
    scene: &Scene,
    fr: &Frame,
    angles: impl Fn(&[[f64; 2]], &[u32], f64, f64, bool) -> Result<contact_angle::ContactAngles, E>,
) -> Result<SeriesRow, E> {
    let nf = fr.n_fluid;
    let (mass, pos, vel, phase) = (&fr.mass[..nf], &fr.pos[..nf], &fr.vel[..nf], &fr.phase[..nf]);
    let c = flow::centroid(mass, pos, phase, 0);
    let m = flow::mass_per_phase(mass, phase, scene.phases.len());
    let rho0: Vec<f64> = scene.phases.iter().map(|p| p.rho0).collect();
    let norm = |v: &[f64; 2]| v[0].hypot(v[1]);
    // Each maximum once, with its particle: the value for the row, the position beside it.
    let (rho_max, speed_max) =
        (flow::argmax_density_error(&fr.rho[..nf], &rho0, phase), flow::argmax_speed(vel, phase));
    let (v_max, a_max) =
        (speed_max.map_or(0.0, |(_, v)| v), fr.acc.get(..nf).map_or(0.0, |a| a.iter().map(norm).fold(0.0, f64::max)));
    let at = |k: Option<(usize, f64)>| k.map(|(i, _)| pos[i]);
    let (rho_at, speed_at) = (at(rho_max), at(speed_max));
    let (limit, tight) = crate::scene::dt_policy::tightest(&crate::scene::dt_policy::state_limits(scene, v_max, a_max));
    let mut row = SeriesRow {
        t: fr.t,
        step: fr.step,
        dt: fr.dt,
        kinetic_energy: flow::kinetic_energy(mass, vel, phase, 0),
        centroid_x: c[0],
        centroid_y: c[1],
        mass_phase0: m[0],
        mass_phase1: m.get(1).copied().unwrap_or(0.0),
        max_density_error: rho_max.map_or(0.0, |(_, e)| e),
        max_speed: v_max,
        dt_limit: if scene.time.dt > 0.0 { "fixed" } else { limit }.into(),
        dt_over_limit: fr.dt / tight,
        max_density_error_x: rho_at.map(|p| p[0]),
        max_density_error_y: rho_at.map(|p| p[1]),
        max_speed_x: speed_at.map(|p| p[0]),
        max_speed_y: speed_at.map(|p| p[1]),
        ..Default::default()
    };
    if let Some(w) = &scene.interface_wave {
        let d = &scene.domain;
        row.wave_amplitude =
            Some(crate::diagnostics::wave::wave_amplitude(pos, phase, d.dx(), d.x[0], d.x[1] - d.x[0], w.k()));
    }
    if scene.contact.mode != ContactMode::None {
        let dx = scene.domain.dx();
        let y_w = scene.domain.y[0];
        let mirrored = scene.domain.left == Side::Mirror;
        let a = angles(pos, phase, dx, y_w, mirrored)?;
        row.theta_two_point = a.two_point;
        row.theta_circle_fit = a.circle_fit;
        row.theta_area = a.area;
        row.x_tp = contact_angle::contact_half_width(pos, phase, dx, y_w);
        if let (Some(x), Some(r0)) = (row.x_tp, initial_radius(scene)) {
            row.spread_factor = Some(if mirrored { x / r0 } else { x / (2.0 * r0) });
        }
    }
    Ok(row)
}

/// Radius of the first circle of phase 0 (the drop), for D/D0.
pub fn initial_radius(scene: &Scene) -> Option<f64> {
    let liquid = &scene.phases[0].name;
    scene.shapes.iter().find(|s| s.kind == ShapeKind::Circle && &s.phase == liquid).and_then(|s| s.radius)
}
