//! Field checks of a scene ([`Scene::validate`]): every number finite and inside its physical
//! range, every name resolvable, every shape touching the box. The error names the field as the
//! user wrote it (its TOML path) and the accepted range. The ranges are wide enough for both
//! nondimensional scenes and SI micro-scale ones (the `impact` scene: Δx ≈ 1e-5 m); they exist
//! to stop values that can only end in overflow (μ = 1e300, ρ0 = 1e-300, γ = 1.8e308) before a
//! run starts. Whether a fixed dt is stable is not checked here, and neither are memory and
//! particle counts (`crate::plan`).

use super::{
    ColourGradient, ContactMode, InitialVelocity, LiquidGasAtWall, Scene, SceneError, ShapeKind, Side, WallTension,
    MAX_FLUID_PHASES,
};

fn err(field: &str, msg: impl Into<String>) -> SceneError {
    SceneError { field: field.to_string(), msg: msg.into() }
}

/// Largest |coordinate| of the domain and shapes.
pub const MAX_COORD: f64 = 1e6;
/// Largest `domain.jitter` (fraction of Δx): a first row 0.5Δx from a wall stays inside it,
/// and no two jittered particles come closer than Δx/2.
pub const MAX_JITTER: f64 = 0.25;
/// Smallest domain extent.
pub const MIN_EXTENT: f64 = 1e-9;
/// Smallest Δx relative to the largest |coordinate| (f64 positions must resolve the lattice).
pub const MIN_DX_REL: f64 = 1e-9;
/// `kernel.h_ratio` range: below it a particle sees almost no neighbour, above it the
/// neighbour lists hold hundreds of entries per particle.
pub const H_RATIO: (f64, f64) = (0.5, 4.0);
/// Rest density range.
pub const RHO0: (f64, f64) = (1e-6, 1e6);
/// Dynamic viscosity range.
pub const MU: (f64, f64) = (0.0, 1e6);
/// Sound speed range.
pub const C0: (f64, f64) = (1e-6, 1e6);
/// Tait exponent range.
pub const GAMMA: (f64, f64) = (1.0, 20.0);
/// Background pressure range, in units of the phase's stiffness B = ρ0c0²/γ.
pub const P_B_OVER_B: (f64, f64) = (0.0, 100.0);
/// Largest |velocity| of a shape or the rod field, and largest |gravity|.
pub const MAX_SPEED: f64 = 1e6;
/// Largest |gravity| component.
pub const MAX_GRAVITY: f64 = 1e6;
/// Surface tension coefficient range (σ, σ_LS, σ_GS).
pub const SIGMA: (f64, f64) = (0.0, 1e6);
/// Contact-line band range (in Δx).
pub const BAND: (f64, f64) = (0.1, 10.0);
/// `walls.beta_max` range.
pub const BETA_MAX: (f64, f64) = (1.0, 1e6);
/// `walls.lj_strength` range.
pub const LJ_STRENGTH: (f64, f64) = (0.0, 1e12);
/// Longest end time / relaxation time.
pub const MAX_TIME: f64 = 1e9;

/// A number as people read it: plain for moderate magnitudes, scientific otherwise.
pub fn num(v: f64) -> String {
    if v == 0.0 || (v.is_finite() && v.abs() >= 1e-4 && v.abs() < 1e7) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `v` finite and inside `[lo, hi]`, else an error naming `field` and the range.
fn in_range(field: &str, v: f64, (lo, hi): (f64, f64), what: &str) -> Result<(), SceneError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(err(field, format!("{what} must be a finite number in [{}, {}], got {}", num(lo), num(hi), num(v))))
    }
}

fn finite_within(field: &str, v: &[f64], max: f64, what: &str) -> Result<(), SceneError> {
    if v.iter().all(|x| x.is_finite() && x.abs() <= max) {
        Ok(())
    } else {
        let shown: Vec<String> = v.iter().map(|x| num(*x)).collect();
        Err(err(field, format!("{what} must be finite with |value| ≤ {}, got [{}]", num(max), shown.join(", "))))
    }
}

/// Checks every field; the error names the first bad one.
pub(super) fn validate(s: &Scene) -> Result<(), SceneError> {
    domain(s)?;
    phases(s)?;
    shapes(s)?;
    interfaces(s)?;
    interface_wave(s)?;
    capillary_rule(s)?;
    time(s)?;
    if s.output.every == 0 {
        return Err(err("output.every", "must be ≥ 1 (a series.csv row every N steps)"));
    }
    Ok(())
}

fn domain(s: &Scene) -> Result<(), SceneError> {
    let d = &s.domain;
    if !(0.0..=MAX_JITTER).contains(&d.jitter) {
        return Err(err(
            "domain.jitter",
            format!("must be within [0, {}] (a fraction of Δx), got {}", num(MAX_JITTER), num(d.jitter)),
        ));
    }
    for (f, v) in [("domain.x", d.x), ("domain.y", d.y)] {
        finite_within(f, &v, MAX_COORD, "both bounds")?;
        if !(v[1] - v[0] >= MIN_EXTENT) {
            return Err(err(
                f,
                format!("need lower < upper with an extent ≥ {}, got [{}, {}]", num(MIN_EXTENT), num(v[0]), num(v[1])),
            ));
        }
    }
    if d.nx == 0 {
        return Err(err("domain.nx", "must be a positive number of particles across x"));
    }
    let dx = d.dx();
    let far = d.x.iter().chain(d.y.iter()).fold(0.0f64, |m, v| m.max(v.abs()));
    if dx < MIN_DX_REL * far {
        return Err(err(
            "domain.nx",
            format!(
                "Δx = {} is below {} × the largest coordinate ({}): positions cannot resolve the lattice",
                num(dx),
                num(MIN_DX_REL),
                num(far)
            ),
        ));
    }
    let ny = (d.y[1] - d.y[0]) / dx;
    if (ny - ny.round()).abs() > 1e-6 * ny.max(1.0) || ny.round() < 1.0 {
        return Err(err(
            "domain.y",
            format!("the height must be a whole number (≥ 1) of Δx = {} = (x1 − x0)/nx, got {} rows", num(dx), num(ny)),
        ));
    }
    if (d.left == Side::Periodic) != (d.right == Side::Periodic) {
        return Err(err("domain.left", "periodic sides come in pairs: left and right must both be periodic"));
    }
    if (d.bottom == Side::Periodic) != (d.top == Side::Periodic) {
        return Err(err("domain.bottom", "periodic sides come in pairs: bottom and top must both be periodic"));
    }
    in_range("kernel.h_ratio", s.kernel.h_ratio, H_RATIO, "h/Δx")?;
    let sup = s.support();
    if d.x[1] - d.x[0] < 2.0 * sup || d.y[1] - d.y[0] < 2.0 * sup {
        return Err(err(
            "domain.nx",
            format!(
                "the box ({} × {}) must span at least two kernel supports 2κh = {}: raise domain.nx (now {}) or lower kernel.h_ratio (now {})",
                num(d.x[1] - d.x[0]),
                num(d.y[1] - d.y[0]),
                num(2.0 * sup),
                d.nx,
                s.kernel.h_ratio
            ),
        ));
    }
    Ok(())
}

fn phases(s: &Scene) -> Result<(), SceneError> {
    if s.phases.is_empty() || s.phases.len() > MAX_FLUID_PHASES {
        return Err(err("phases", format!("need 1 to {MAX_FLUID_PHASES} fluid phases, got {}", s.phases.len())));
    }
    for (i, p) in s.phases.iter().enumerate() {
        let f = |n: &str| format!("phases[{i}].{n}");
        if p.name.is_empty() || p.name == "*" {
            return Err(err(&f("name"), "must be a non-empty name other than `*`"));
        }
        if s.phases.iter().filter(|q| q.name == p.name).count() > 1 {
            return Err(err(&f("name"), format!("duplicate phase name `{}`", p.name)));
        }
        in_range(&f("rho0"), p.rho0, RHO0, "the rest density")?;
        in_range(&f("mu"), p.mu, MU, "the dynamic viscosity")?;
        in_range(&f("c0"), p.c0, C0, "the sound speed")?;
        in_range(&f("gamma"), p.gamma, GAMMA, "the Tait exponent")?;
        let b = crate::physics::eos::eos_stiffness(p.rho0, p.c0, p.gamma);
        let range = (P_B_OVER_B.0 * b, P_B_OVER_B.1 * b);
        if !(p.p_b.is_finite() && p.p_b >= range.0 && p.p_b <= range.1) {
            return Err(err(
                &f("p_b"),
                format!(
                    "the background pressure must lie in [0, {}·B] = [0, {}] (B = ρ0c0²/γ = {}), got {}",
                    P_B_OVER_B.1,
                    num(range.1),
                    num(b),
                    num(p.p_b)
                ),
            ));
        }
    }
    if s.phase_index(&s.fill).is_none() {
        return Err(err("fill", format!("unknown phase `{}` (phases: {})", s.fill, phase_names(s))));
    }
    Ok(())
}

fn phase_names(s: &Scene) -> String {
    s.phases.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ")
}

fn shapes(s: &Scene) -> Result<(), SceneError> {
    let d = &s.domain;
    for (i, sh) in s.shapes.iter().enumerate() {
        let f = |n: &str| format!("shapes[{i}].{n}");
        if s.phase_index(&sh.phase).is_none() {
            return Err(err(&f("phase"), format!("unknown phase `{}` (phases: {})", sh.phase, phase_names(s))));
        }
        finite_within(&f("velocity"), &sh.velocity, MAX_SPEED, "both components")?;
        // Bounding box of the shape; it must overlap the domain.
        let (lo, hi) = match sh.kind {
            ShapeKind::Circle => {
                let c = sh.centre.ok_or_else(|| err(&f("centre"), "a circle needs a centre [x, y]"))?;
                finite_within(&f("centre"), &c, MAX_COORD, "both coordinates")?;
                let r = sh.radius.ok_or_else(|| err(&f("radius"), "a circle needs a radius"))?;
                in_range(&f("radius"), r, (MIN_EXTENT, MAX_COORD), "the radius")?;
                ([c[0] - r, c[1] - r], [c[0] + r, c[1] + r])
            }
            ShapeKind::Rect => {
                let a = sh.min.ok_or_else(|| err(&f("min"), "a rectangle needs min [x, y]"))?;
                let b = sh.max.ok_or_else(|| err(&f("max"), "a rectangle needs max [x, y]"))?;
                finite_within(&f("min"), &a, MAX_COORD, "both coordinates")?;
                finite_within(&f("max"), &b, MAX_COORD, "both coordinates")?;
                if !(a[0] < b[0] && a[1] < b[1]) {
                    return Err(err(
                        &f("max"),
                        format!("a rectangle needs min < max in x and y, got min {a:?}, max {b:?}"),
                    ));
                }
                (a, b)
            }
        };
        if hi[0] <= d.x[0] || lo[0] >= d.x[1] || hi[1] <= d.y[0] || lo[1] >= d.y[1] {
            let field = if sh.kind == ShapeKind::Circle { f("centre") } else { f("min") };
            return Err(err(
                &field,
                format!(
                    "the shape lies outside the domain [{}, {}] × [{}, {}] (its extent: [{}, {}] × [{}, {}])",
                    num(d.x[0]),
                    num(d.x[1]),
                    num(d.y[0]),
                    num(d.y[1]),
                    num(lo[0]),
                    num(hi[0]),
                    num(lo[1]),
                    num(hi[1])
                ),
            ));
        }
    }
    Ok(())
}

fn interfaces(s: &Scene) -> Result<(), SceneError> {
    if let Some(st) = &s.surface_tension {
        in_range("surface_tension.sigma", st.sigma, SIGMA, "σ")?;
        if s.phases.len() < 2 {
            return Err(err("surface_tension", "needs two fluid phases (remove [surface_tension] or add a phase)"));
        }
        if st.colour_gradient == ColourGradient::SingleField && s.contact.mode != ContactMode::None {
            return Err(err(
                "surface_tension.colour_gradient",
                "`single-field` works without a contact-angle model only (contact.mode = \"none\"); use `thesis`",
            ));
        }
    }
    let c = &s.contact;
    if c.mode != ContactMode::None {
        if s.surface_tension.is_none() {
            return Err(err("contact.mode", "a contact-angle mode needs [surface_tension]"));
        }
        if !s.domain.bottom.is_wall() {
            return Err(err(
                "contact.mode",
                "the contact line lives on the bottom wall, so domain.bottom must be no-slip or free-slip",
            ));
        }
    }
    if c.wall_tension != WallTension::Bands {
        let name = if c.wall_tension == WallTension::Line { "line" } else { "unbalanced" };
        if c.mode != ContactMode::A {
            return Err(err(
                "contact.wall_tension",
                format!("`{name}` places Mode A's wall tensions; set contact.mode = \"a\" or use `bands`"),
            ));
        }
        if c.line_force {
            return Err(err(
                "contact.line_force",
                format!("with contact.wall_tension = \"{name}\" the line force already carries the whole σ_GS − σ_LS; set it false"),
            ));
        }
    }
    if c.wall_tension == WallTension::Unbalanced {
        if !c.wall_typing {
            return Err(err(
                "contact.wall_typing",
                "contact.wall_tension = \"unbalanced\" continues the liquid–gas band into the typed wall; set it true",
            ));
        }
        if c.liquid_gas_at_wall != LiquidGasAtWall::Shared {
            return Err(err(
                "contact.liquid_gas_at_wall",
                "with contact.wall_tension = \"unbalanced\" the typed wall holds the band's end through the fluid's whole tensor; use `shared`",
            ));
        }
    }
    in_range("contact.sigma_ls", c.sigma_ls, SIGMA, "σ_LS")?;
    in_range("contact.sigma_gs", c.sigma_gs, SIGMA, "σ_GS")?;
    if !(c.theta_deg > 0.0 && c.theta_deg < 180.0) {
        return Err(err("contact.theta_deg", format!("must lie in (0, 180) degrees, got {}", num(c.theta_deg))));
    }
    in_range("contact.band", c.band, BAND, "the band (in Δx)")?;
    if let Some(w) = &s.walls.phase {
        if s.phase_index(w).is_none() {
            return Err(err("walls.phase", format!("unknown phase `{w}` (phases: {})", phase_names(s))));
        }
    }
    in_range("walls.beta_max", s.walls.beta_max, BETA_MAX, "β_max")?;
    in_range("walls.lj_strength", s.walls.lj_strength, LJ_STRENGTH, "the Lennard-Jones strength")?;
    finite_within("gravity", &s.gravity, MAX_GRAVITY, "both components")?;
    Ok(())
}

/// The capillary rule's constants: α ≥ 0 (0 is the thesis's p_b = 0), 0 < ε ≤ 1, and a σ to
/// take the band tension from.
/// The fields the capillary rule derives p_b and c0 from (resolution and kernel, the phases'
/// densities and exponents, σ), checked before it runs so that a bad value is named itself,
/// not through the sound speed it would make.
pub(super) fn rule_inputs(s: &Scene) -> Result<(), SceneError> {
    domain(s)?;
    phases(s)?;
    interfaces(s)
}

pub(super) fn capillary_rule(s: &Scene) -> Result<(), SceneError> {
    let Some(r) = &s.capillary_rule else { return Ok(()) };
    if !(r.alpha.is_finite() && (0.0..=100.0).contains(&r.alpha)) {
        return Err(err("capillary_rule.alpha", format!("must be in [0, 100], got {}", num(r.alpha))));
    }
    if !(r.epsilon.is_finite() && r.epsilon > 0.0 && r.epsilon <= 1.0) {
        return Err(err("capillary_rule.epsilon", format!("must be in (0, 1], got {}", num(r.epsilon))));
    }
    if s.surface_tension.as_ref().is_none_or(|t| t.sigma <= 0.0) {
        return Err(err("capillary_rule", "needs surface_tension.sigma > 0 (the band tension σ|∇C|/2)"));
    }
    Ok(())
}

fn time(s: &Scene) -> Result<(), SceneError> {
    let t = &s.time;
    in_range("time.t_end", t.t_end, (f64::MIN_POSITIVE, MAX_TIME), "the end time")?;
    if !(t.t_end > 0.0) {
        return Err(err("time.t_end", "must be positive"));
    }
    if !(t.dt.is_finite() && t.dt >= 0.0 && t.dt < t.t_end) {
        return Err(err(
            "time.dt",
            format!(
                "must lie in [0, time.t_end = {}) (0 = automatic from the stability limits), got {}",
                num(t.t_end),
                num(t.dt)
            ),
        ));
    }
    if !(t.cfl > 0.0 && t.cfl <= 1.0) {
        return Err(err("time.cfl", format!("must lie in (0, 1], got {}", num(t.cfl))));
    }
    in_range("time.xsph", t.xsph, (0.0, 1.0), "XSPH ε")?;
    if let Some(r) = &s.relax {
        in_range("relax.t", r.t, (0.0, MAX_TIME), "the relaxation time")?;
        if r.t > 0.0 && t.dt > 0.0 && r.t < t.dt {
            return Err(err("relax.t", format!("must be 0 or at least time.dt = {}, got {}", num(t.dt), num(r.t))));
        }
    }
    if let Some(InitialVelocity::RodOscillation { v0, r0, centre, phase }) = &s.initial_velocity {
        if phase != "*" && s.phase_index(phase).is_none() {
            return Err(err("initial_velocity.phase", format!("unknown phase `{phase}` ({}, or `*`)", phase_names(s))));
        }
        in_range("initial_velocity.v0", *v0, (-MAX_SPEED, MAX_SPEED), "V0")?;
        in_range("initial_velocity.r0", *r0, (MIN_EXTENT, MAX_COORD), "r0")?;
        finite_within("initial_velocity.centre", centre, MAX_COORD, "both coordinates")?;
    }
    Ok(())
}

/// `[interface_wave]`: the wavelength fits the box (a whole number of wavelengths between
/// periodic sides, of half-wavelengths between any others, where the displacement's
/// horizontal part vanishes), bottom and top are impermeable, y0 is an inner lattice line,
/// k|a0|·coth(kH) ≤ [`MAX_KA`].
fn interface_wave(s: &Scene) -> Result<(), SceneError> {
    let Some(w) = &s.interface_wave else { return Ok(()) };
    let d = &s.domain;
    let width = d.x[1] - d.x[0];
    in_range("interface_wave.wavelength", w.wavelength, (MIN_EXTENT, MAX_COORD), "λ")?;
    let unit = if d.left == Side::Periodic { w.wavelength } else { 0.5 * w.wavelength };
    let fits = width / unit;
    if (fits - fits.round()).abs() > 1e-6 * fits.max(1.0) || fits.round() < 1.0 {
        let what = if d.left == Side::Periodic { "wavelengths (periodic sides)" } else { "half-wavelengths" };
        return Err(err(
            "interface_wave.wavelength",
            format!(
                "the domain width {} must be a whole number (≥ 1) of {what}, got λ = {}",
                num(width),
                num(w.wavelength)
            ),
        ));
    }
    if d.bottom == Side::Periodic {
        return Err(err(
            "interface_wave",
            "needs impermeable bottom and top sides (mirror, no-slip or free-slip), not periodic ones",
        ));
    }
    let dx = d.dx();
    let rows = (w.y0 - d.y[0]) / dx;
    if !(rows.is_finite() && (rows - rows.round()).abs() <= 1e-6 * rows.abs().max(1.0))
        || rows.round() < 1.0
        || rows.round() >= d.ny() as f64
    {
        return Err(err(
            "interface_wave.y0",
            format!(
                "must be an inner lattice line y[0] + jΔx (0 < j < {}, Δx = {}) in ({}, {}), got {}",
                d.ny(),
                num(dx),
                num(d.y[0]),
                num(d.y[1]),
                num(w.y0)
            ),
        ));
    }
    let depth = (w.y0 - d.y[0]).min(d.y[1] - w.y0);
    let max_a = super::wave::MAX_KA / w.k() * (w.k() * depth).tanh();
    in_range("interface_wave.amplitude", w.amplitude, (-max_a, max_a), "the amplitude (k|a0|·coth(kH) ≤ 0.5)")?;
    Ok(())
}
