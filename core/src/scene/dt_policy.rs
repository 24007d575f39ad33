//! A fixed `time.dt` against the stability limits (docs/PHYSICS.md §7.3, [`DtLimits`]) at load:
//! the CFL, viscous, force and capillary limits at the scene's resolution, phases and σ, with
//! `|v|_max` the largest initial speed (shape velocities, the analytic field) and `|a|_max` the
//! body force (the only acceleration known before the first evaluation; the running check uses
//! the measured one). `time.dt_policy` says what a dt above a limit does:
//!
//! * `strict` (default): refused (exit 2), naming each limit, its value, its inputs and the
//!   largest safe dt;
//! * `warn`: a warning, and the run goes ahead;
//! * `scale`: `dt` was chosen at `time.dt_nx` and keeps the fraction of the tightest limit it has
//!   there: `dt(nx) = dt · min limits(nx) / min limits(dt_nx)`. Where the same limit binds at both
//!   resolutions this is that limit's power of Δx (CFL: Δx, the study's `1e-4·30/nx`; viscous:
//!   Δx², the convergence cases); where another limit takes over it follows that one, so a dt
//!   safe at `dt_nx` stays safe at every resolution (under the capillary rule the limits at
//!   `dt_nx` take the rule's c0 there). The scaled dt is then checked as `strict`.
//!
//! [`apply`] is the one check at load (`run::run`, the study's and the stability map's scenes);
//! [`effective_dt`] is what the solvers use (`Model::new`), so every path sees the same dt.

use super::{DtPolicy, InitialVelocity, Scene, SceneError};
use crate::physics::timestep::DtLimits;

/// The limits of a scene at load, with the inputs they came from.
#[derive(Clone, Debug)]
pub struct LoadLimits {
    /// The four limits.
    pub limits: DtLimits,
    /// Resolution they are computed at.
    pub nx: u32,
    /// Smoothing length h.
    pub h: f64,
    /// Largest sound speed and the field it comes from.
    pub c_max: (f64, String),
    /// Largest initial speed and where it comes from.
    pub v_max: (f64, String),
    /// Largest kinematic viscosity μ/ρ0 and the phase it comes from.
    pub nu_max: (f64, String),
    /// Body-force magnitude |g|.
    pub a_max: f64,
    /// Mean rest density of the phases.
    pub rho_mean: f64,
    /// Largest σ and the field it comes from.
    pub sigma_max: (f64, String),
    /// The CFL factor.
    pub cfl: f64,
}

/// Names of the limits, in [`DtLimits`] order.
pub const LIMIT_NAMES: [&str; 4] = ["cfl", "viscous", "force", "capillary"];

impl LoadLimits {
    /// `(name, value)` of every limit, in [`LIMIT_NAMES`] order.
    pub fn named(&self) -> [(&'static str, f64); 4] {
        named(&self.limits)
    }
    /// The tightest limit and its name.
    pub fn tightest(&self) -> (&'static str, f64) {
        tightest(&self.limits)
    }
    /// The formula and inputs of limit `name`, for messages.
    pub fn explain(&self, name: &str) -> String {
        let h = self.h;
        match name {
            "cfl" => format!(
                "cfl·h/(c_max + |v|_max) with cfl = {} (time.cfl), h = {h:.4e}, c_max = {} ({}), |v|_max = {:.4} ({})",
                self.cfl, self.c_max.0, self.c_max.1, self.v_max.0, self.v_max.1
            ),
            "viscous" => {
                format!("0.125·h²/ν_max with h = {h:.4e}, ν_max = μ/ρ0 = {:.4e} ({})", self.nu_max.0, self.nu_max.1)
            }
            "force" => format!("0.125·sqrt(h/|a|_max) with h = {h:.4e}, |a|_max = |gravity| = {}", self.a_max),
            _ => format!(
                "0.25·sqrt(ρ̄h³/(2πσ_max)) with h = {h:.4e}, ρ̄ = {} (mean of the phases' rho0), σ_max = {} ({})",
                self.rho_mean, self.sigma_max.0, self.sigma_max.1
            ),
        }
    }
}

/// `(name, value)` of every limit.
pub fn named(l: &DtLimits) -> [(&'static str, f64); 4] {
    [("cfl", l.cfl), ("viscous", l.viscous), ("force", l.force), ("capillary", l.capillary)]
}

/// The tightest limit and its name (the first of equal ones).
pub fn tightest(l: &DtLimits) -> (&'static str, f64) {
    named(l).into_iter().fold(("cfl", f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a })
}

/// Largest initial speed: shape velocities, and the rod field sampled on a fine polar grid
/// about its centre (resolution-independent, so `scale` rescales exactly with the limits).
fn initial_speed(scene: &Scene) -> (f64, String) {
    let mut best = (0.0, "at rest".to_string());
    for (i, s) in scene.shapes.iter().enumerate() {
        let v = s.velocity[0].hypot(s.velocity[1]);
        if v > best.0 {
            best = (v, format!("shapes[{i}].velocity"));
        }
    }
    if let Some(InitialVelocity::RodOscillation { v0, r0, .. }) = &scene.initial_velocity {
        let mut vmax: f64 = 0.0;
        let (nr, nt) = (400, 360);
        for a in 1..=nr {
            let r = 20.0 * r0 * a as f64 / nr as f64;
            for b in 0..nt {
                let th = std::f64::consts::TAU * b as f64 / nt as f64;
                let v = super::initial::rod_velocity(*v0, *r0, r * th.cos(), r * th.sin(), 0.0);
                vmax = vmax.max(v[0].hypot(v[1]));
            }
        }
        if vmax > best.0 {
            best = (vmax, "initial_velocity (rod field)".into());
        }
    }
    best
}

/// The limits of `scene` at resolution `nx` (the scene's own phases, σ, kernel and box) at load.
pub fn limits_at(scene: &Scene, nx: u32) -> LoadLimits {
    let a_max = scene.gravity[0].hypot(scene.gravity[1]);
    limits_with(scene, nx, initial_speed(scene), a_max)
}

/// The limits of a running state: `v_max`, `a_max` measured (series rows, the GPU monitor).
pub fn state_limits(scene: &Scene, v_max: f64, a_max: f64) -> DtLimits {
    limits_with(scene, scene.domain.nx, (v_max, "state".into()), a_max).limits
}

fn limits_with(scene: &Scene, nx: u32, v_max: (f64, String), a_max: f64) -> LoadLimits {
    let d = &scene.domain;
    let h = scene.kernel.h_ratio * (d.x[1] - d.x[0]) / nx as f64;
    let max_by = |f: &dyn Fn(&super::Phase) -> f64, field: &str| {
        scene
            .phases
            .iter()
            .enumerate()
            .map(|(i, p)| (f(p), format!("phases[{i}].{field}")))
            .fold((0.0, String::from("-")), |a, b| if b.0 > a.0 { b } else { a })
    };
    let c_max = max_by(&|p| p.c0, "c0");
    let nu_max = max_by(&|p| p.mu / p.rho0, "mu/rho0");
    let mut sigma_max = (scene.surface_tension.as_ref().map_or(0.0, |s| s.sigma), "surface_tension.sigma".to_string());
    if scene.contact.mode == super::ContactMode::A {
        for (v, f) in [(scene.contact.sigma_ls, "contact.sigma_ls"), (scene.contact.sigma_gs, "contact.sigma_gs")] {
            if v > sigma_max.0 {
                sigma_max = (v, f.into());
            }
        }
    }
    if scene.phases.len() < 2 && scene.contact.mode != super::ContactMode::A {
        sigma_max.0 = 0.0;
    }
    let rho_mean = scene.phases.iter().map(|p| p.rho0).sum::<f64>() / scene.phases.len() as f64;
    let cfl = scene.time.cfl;
    let limits = DtLimits::compute(h, cfl, c_max.0, v_max.0, nu_max.0, a_max, rho_mean, sigma_max.0);
    LoadLimits { limits, nx, h, c_max, v_max, nu_max, a_max, rho_mean, sigma_max, cfl }
}

/// The resolution `time.dt` was chosen at.
fn dt_nx(scene: &Scene) -> u32 {
    if scene.time.dt_nx == 0 {
        scene.domain.nx
    } else {
        scene.time.dt_nx
    }
}

/// The dt the solvers use: `time.dt`, rescaled to `domain.nx` under `scale` (0 stays automatic).
pub fn effective_dt(scene: &Scene) -> f64 {
    let t = &scene.time;
    if t.dt <= 0.0 || t.dt_policy != DtPolicy::Scale || dt_nx(scene) == scene.domain.nx {
        return t.dt;
    }
    let at = limits_at(scene, scene.domain.nx).tightest().1;
    // Under the capillary rule c0 follows the resolution: the limits at dt_nx take its c0 there.
    let mut base = scene.clone();
    if base.capillary_rule.is_some() {
        base.domain.nx = dt_nx(scene);
        super::capillary::apply(&mut base);
    }
    let from = limits_at(&base, dt_nx(scene)).tightest().1;
    if at.is_finite() && from.is_finite() {
        t.dt * at / from
    } else {
        t.dt * dt_nx(scene) as f64 / scene.domain.nx as f64
    }
}

/// What [`apply`] decided.
#[derive(Clone, Debug)]
pub struct Applied {
    /// The scene with `time.dt` the effective dt (and `time.dt_nx = domain.nx`).
    pub scene: Scene,
    /// The limits at the scene's resolution.
    pub limits: LoadLimits,
    /// Limits the dt is above (only under `warn`; `strict` and `scale` refuse them).
    pub warnings: Vec<String>,
}

/// The check at load: the scene with its effective dt, or a bad-input error (field `time.dt`)
/// naming every limit the dt is above, its value and inputs, and the largest safe dt.
pub fn apply(scene: &Scene) -> Result<Applied, SceneError> {
    let mut out = scene.clone();
    let dt = effective_dt(scene);
    out.time.dt = dt;
    out.time.dt_nx = if dt > 0.0 { scene.domain.nx } else { scene.time.dt_nx };
    let limits = limits_at(scene, scene.domain.nx);
    if dt <= 0.0 {
        return Ok(Applied { scene: out, limits, warnings: vec![] });
    }
    let over: Vec<String> = limits
        .named()
        .into_iter()
        .filter(|&(_, v)| dt > v)
        .map(|(n, v)| format!("{n} limit {v:.4e} = {} (dt/limit = {:.2})", limits.explain(n), dt / v))
        .collect();
    if over.is_empty() {
        return Ok(Applied { scene: out, limits, warnings: vec![] });
    }
    let (tn, tv) = limits.tightest();
    let scaled = if scene.time.dt_policy == DtPolicy::Scale {
        format!(" (time.dt = {:e} chosen at time.dt_nx = {}, scaled to {dt:.4e})", scene.time.dt, dt_nx(scene))
    } else {
        String::new()
    };
    let msg = format!(
        "dt = {dt:.4e}{scaled} is above {} at domain.nx = {}: {}; the largest safe dt is {tv:.4e} (the {tn} limit): \
         set time.dt ≤ {tv:.4e}, {}, or time.dt_policy = \"warn\" to run anyway",
        if over.len() == 1 { "a stability limit" } else { "stability limits" },
        scene.domain.nx,
        over.join("; "),
        if scene.time.dt_nx != 0 && scene.time.dt_nx != scene.domain.nx && scene.time.dt_policy != DtPolicy::Scale {
            format!("time.dt_policy = \"scale\" (rescales dt from time.dt_nx = {})", scene.time.dt_nx)
        } else {
            "time.dt_policy = \"scale\" with time.dt_nx = the resolution dt was chosen at".into()
        }
    );
    match scene.time.dt_policy {
        DtPolicy::Warn => Ok(Applied { scene: out, limits, warnings: over }),
        DtPolicy::Strict | DtPolicy::Scale => Err(SceneError { field: "time.dt".into(), msg }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin::{builtin, BUILTIN};

    #[test]
    fn every_builtin_passes_strict_at_its_resolution() {
        for name in BUILTIN {
            let s = builtin(name).unwrap();
            let a = apply(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(a.scene.time.dt, s.time.dt, "{name}: strict never changes dt");
        }
    }

    #[test]
    fn scale_is_identity_at_dt_nx_and_linear_where_cfl_binds() {
        let mut s = builtin("oscillating-drop").unwrap();
        s.time.dt_policy = DtPolicy::Scale;
        assert_eq!(effective_dt(&s), 1e-4);
        s.domain.nx = 60;
        assert!((effective_dt(&s) / 5e-5 - 1.0).abs() < 1e-12, "{}", effective_dt(&s));
    }
}
