//! Built-in scenes, exactly as docs/PHYSICS.md §9 sets them up, plus a single-phase Poiseuille flow
//! and Prosperetti's capillary wave (§9(f)), both with analytic answers. `sphlab scene show NAME` prints any of them as editable TOML.

use super::*;
use crate::physics::kernel::KernelKind;

/// Names of the built-in scenes.
pub const BUILTIN: [&str; 7] =
    ["oscillating-drop", "sessile-90", "relax-60", "impact", "poiseuille", "capillary-wave", "capillary-wave-1000"];

/// A built-in scene by name.
pub fn builtin(name: &str) -> Option<Scene> {
    Some(match name {
        "oscillating-drop" => oscillating_drop(),
        "sessile-90" => sessile(90.0),
        "relax-60" => relax_60(),
        "impact" => impact(90.0),
        "poiseuille" => poiseuille(),
        "capillary-wave" => capillary_wave(1.0),
        "capillary-wave-1000" => capillary_wave(1000.0),
        _ => return None,
    })
}

/// Midpoint stepping with automatic dt (CFL 0.25, strict policy, no XSPH) to `t_end`: the time
/// set-up of the built-ins without a fixed thesis dt.
fn adaptive_time(t_end: f64) -> Time {
    Time {
        integrator: Integrator::Midpoint,
        dt: 0.0,
        cfl: 0.25,
        t_end,
        xsph: 0.0,
        dt_policy: DtPolicy::Strict,
        dt_nx: 0,
        background: Background::Momentum,
    }
}

fn fluid(name: &str, rho0: f64, mu: f64, c0: f64, gamma: f64) -> Phase {
    Phase { name: name.into(), rho0, mu, c0, gamma, p_b: 0.0 }
}

/// The background pressure of a two-phase built-in at lattice spacing `dx`:
/// `p_b = σ/(2Δx)`. The Hu–Adams stress puts a tensile normal stress `σ|∇C|/2 ≈ 0.23σ/Δx`
/// on the interface band (first-row |∇C| = 0.4628/Δx on a flat interface, `tests/surface_tension.rs`)
/// which the pressure must carry without going negative, or voids open along the interface;
/// `σ/(2Δx)` is about twice that. Larger values cost: the pressure-sum error on disordered
/// particles times p_b acts as an elastic spring on the arrangement (p_b = B = 175 made the
/// cubic-spline and Wendland drops ring at T ≈ 0.19 like a solid). Measured against p_b in
/// `reports/validation/pb-sweep/` (spurious speed, Laplace jump, voids, period, three kernels).
pub fn capillary_background_pressure(sigma: f64, dx: f64) -> f64 {
    sigma / (2.0 * dx)
}

/// First-row |∇C|·Δx on a flat interface (`tests/surface_tension.rs`): the Hu–Adams stress's
/// tensile normal stress on the interface band is `σ|∇C|/2 = 0.2314σ/Δx`.
pub const FLAT_FIRST_ROW_GRAD: f64 = 0.4628;

/// p_b of a moving contact line in units of the capillary pressure σ/R (`relax-60` and the
/// convergence case): 11.25, the value σ/(2Δx) takes at the thesis's coarsest 0.5/45 with R = 0.25.
pub const MOVING_CONTACT_PB_PER_CAPILLARY: f64 = 11.25;

/// The background pressure of a drop whose contact line has to move (`relax-60`, convergence;
/// ): fixed in units of the capillary pressure, `p_b = 11.25·σ/R` (45 for R = 0.25),
/// floored at the interface band's tensile stress `0.2314σ/Δx` (binds from nx ≈ 98 across 0.5).
/// A rule that grows with 1/Δx pins the contact line more at every refinement: under
/// σ/(2Δx) θ ended at 61.6°, 66.5°, 68.8°, 70.3° at nx = 45, 65, 85, 105; under this rule
/// θ 61.6°, 61.0°, 62.2°, 63.4° and D/D0 at the wall 1.350, 1.378, 1.380, 1.353
/// (`reports/validation/convergence/pb-check/README.md`). The price is motion: 5× (nx = 65) to
/// 45× (nx = 105) the liquid kinetic energy of the σ/(2Δx) runs.
pub fn moving_contact_background_pressure(sigma: f64, radius: f64, dx: f64) -> f64 {
    (MOVING_CONTACT_PB_PER_CAPILLARY * sigma / radius).max(0.5 * FLAT_FIRST_ROW_GRAD * sigma / dx)
}

/// The background pressure of a drop at rest on a wall (`sessile-90`): `p_b = σ/Δx`,
/// twice [`capillary_background_pressure`]. Nothing has to move there, so the spring p_b puts
/// on the arrangement costs nothing and buys order: at nx = 45, Mode B over t ∈ [1, 2], p_b = 45
/// (σ/(2Δx)) left the liquid's kinetic energy at 2.6e-6 and the Fig. 4.9 normal deviation at
/// 10.4°, p_b = 65 and 90 at 2e-7 and 6.2–7.7° (`reports/validation/sessile-90/pb-check/`).
/// A moving contact line needs a lower p_b: a higher one pins it
/// ([`moving_contact_background_pressure`]: relax-60, convergence).
pub fn at_rest_background_pressure(sigma: f64, dx: f64) -> f64 {
    sigma / dx
}

/// The background pressure of the transport-velocity formulation (`time.background =
/// "transport"`): `ρ0c0²`, as Adami, Hu & Adams 2013 and PySPH's TVF scheme take it. Below it the
/// shift is too weak to keep the particles ordered against the interface tension (relax-60 at
/// nx = 25: p_b 25 and 100 over-spread to D/D0 1.72 and 1.48; `reports/validation/pb-sweep/`).
pub fn transport_background_pressure(rho0: f64, c0: f64) -> f64 {
    rho0 * c0 * c0
}

/// Two fluid phases of equal density and viscosity with the background pressure `p_b`.
fn equal_phases(mu: f64, c0: f64, p_b: f64) -> Vec<Phase> {
    vec![Phase { p_b, ..fluid("liquid", 1.0, mu, c0, 7.0) }, Phase { p_b, ..fluid("gas", 1.0, mu, c0, 7.0) }]
}

/// §9(a): quarter of a 1×1 box, R = 0.1875 drop of equal density and viscosity, σ = 1,
/// 30×30 particles (Δx = 1/60), relaxed for t = 0.5 and then given the T84 velocity field.
/// The field is applied to every fluid particle, as in Adami 2010 / PySPH `oscillating_rod.py`
/// (`--set initial_velocity.phase=liquid` applies it to the drop only, as the thesis text says;
/// that start gives about half the thesis's centroid amplitude, see reports/validation).
pub fn oscillating_drop() -> Scene {
    Scene {
        name: "oscillating-drop".into(),
        description:
            "Thesis §4.2.1 / Fig. 4.1: oscillating 2D drop (Adami 2010 rod), quarter domain with two symmetry planes"
                .into(),
        domain: Domain {
            x: [0.0, 0.5],
            y: [0.0, 0.5],
            nx: 30,
            left: Side::Mirror,
            right: Side::NoSlip,
            bottom: Side::Mirror,
            top: Side::NoSlip,
        },
        // Quintic with h = 1.2Δx (support 3.6Δx; the thesis gives no h): at nx = 30, p_b = 30 the
        // wider support smooths ∇C and the pressure sum on the disordered arrangement. Measured
        // (reports/validation/oscillation, spurious): h = Δx gave a first-cycle
        // amplitude of 0.0093 (22 % under the thesis's 0.012) and spurious bursts to 0.19; h = 1.2Δx
        // gives 0.0100 (−17 %), T = 0.366, and at rest max speed 0.076, Laplace jump −1.5 % (t = 1).
        kernel: KernelCfg { kind: KernelKind::Quintic, h_ratio: 1.2 },
        // μ = 0.05, σ = 1 (thesis §4.2.1); p_b = σ/(2Δx) = 30 at Δx = 1/60.
        phases: equal_phases(0.05, 35.0, capillary_background_pressure(1.0, 0.5 / 30.0)),
        fill: "gas".into(),
        shapes: vec![Shape::circle([0.0, 0.0], 0.1875, "liquid", [0.0, 0.0])],
        surface_tension: Some(SurfaceTension::thesis(1.0)),
        contact: Contact::default(),
        walls: Walls::default(),
        gravity: [0.0, 0.0],
        time: Time {
            integrator: Integrator::Midpoint,
            dt: 1e-4,
            cfl: 0.25,
            t_end: 0.6,
            xsph: 0.0,
            dt_policy: DtPolicy::Strict,
            dt_nx: 30,
            background: Background::Momentum,
        },
        relax: Some(Relax { t: 0.5 }),
        initial_velocity: Some(InitialVelocity::RodOscillation {
            v0: 10.0,
            r0: 0.05,
            centre: [0.0, 0.0],
            phase: "*".into(),
        }),
        interface_wave: None,
        output: Output { every: 20 },
    }
}

/// §9(b): half-circle drop R = 0.25 on a no-slip wall, symmetry at x = 0, 65×65 particles,
/// ρ = 1, μ = 0.15, σ = 1, Mode B at θ_d (Mode A coefficients all 1 for `--set contact.mode=a`).
/// Cubic spline with h = 1.2Δx and dt = 7e-5 reproduce the thesis (docs/PHYSICS.md §7.4).
pub fn sessile(theta_deg: f64) -> Scene {
    Scene {
        name: "sessile-90".into(),
        description: "Thesis §4.2.2 / Figs. 4.3–4.9: stationary 90° drop on a no-slip wall, symmetry at x = 0".into(),
        domain: Domain {
            x: [0.0, 0.5],
            y: [0.0, 0.5],
            nx: 65,
            left: Side::Mirror,
            right: Side::NoSlip,
            bottom: Side::NoSlip,
            top: Side::NoSlip,
        },
        kernel: KernelCfg { kind: KernelKind::CubicSpline, h_ratio: 1.2 },
        // μ = 0.15 (thesis §4.2.2: "equal density and viscosity of 1.0 and 0.15"), σ = 1;
        // p_b = σ/Δx = 130 at Δx = 0.5/65 (a drop at rest; relax-60 takes 11.25σ/R = 45).
        phases: equal_phases(0.15, 20.0, at_rest_background_pressure(1.0, 0.5 / 65.0)),
        fill: "gas".into(),
        shapes: vec![Shape::circle([0.0, 0.0], 0.25, "liquid", [0.0, 0.0])],
        surface_tension: Some(SurfaceTension::thesis(1.0)),
        contact: Contact {
            mode: ContactMode::B,
            sigma_ls: 1.0,
            sigma_gs: 1.0,
            theta_deg,
            normal_correction: true,
            wall_typing: true,
            band: 1.2,
        },
        walls: Walls::default(),
        gravity: [0.0, 0.0],
        time: Time {
            integrator: Integrator::Midpoint,
            dt: 7e-5,
            cfl: 0.25,
            t_end: 5.0,
            xsph: 0.0,
            dt_policy: DtPolicy::Strict,
            dt_nx: 65,
            background: Background::Momentum,
        },
        relax: None,
        initial_velocity: None,
        interface_wave: None,
        output: Output { every: 500 },
    }
}

/// §9(c): the sessile set-up with targets switched to 60° at t = 0
/// (Mode B θ_d = 60°; Mode A σ_LS = 0.5, σ_GS = 1). Free-slip: `--set domain.bottom=free-slip`.
/// μ = 0.05: thesis §4.2.3 sets the drop up "with properties similar to those mentioned in
/// section 4.2.1" (ρ = 1, μ = 5·10⁻²), not §4.2.2's 0.15.
pub fn relax_60() -> Scene {
    let mut s = sessile(60.0);
    s.name = "relax-60".into();
    s.description = "Thesis §4.2.3 / Figs. 4.10–4.15: 90° drop relaxing to 60° (D/D0 → 1.385)".into();
    for p in &mut s.phases {
        p.mu = 0.05;
        // The contact line moves: p_b = 11.25σ/R = 45, fixed in capillary units (a p_b growing
        // with 1/Δx pins it more at every refinement; convergence case).
        p.p_b = moving_contact_background_pressure(1.0, 0.25, 0.5 / 65.0);
    }
    s.contact.sigma_ls = 0.5;
    s.contact.sigma_gs = 1.0;
    s
}

/// §9(e): 2D water drop (D0 = 500 µm, 1 m/s) hitting a wall in air, 100×100 particles on a
/// 1125 µm half domain, Re = 440, We = 6.86, constant contact angle θ_d (Mode B), R-wall pressure.
pub fn impact(theta_deg: f64) -> Scene {
    let b = 1000.0 * 20.0 * 20.0 / 7.0;
    let c_air = (1.4 * b / 1.2_f64).sqrt();
    Scene {
        name: "impact".into(),
        description: "Thesis §5.2 / Figs. 5.3–5.5: 2D drop impact, Re = 440, We = 6.86, density ratio 833".into(),
        domain: Domain {
            x: [0.0, 1125e-6],
            y: [0.0, 1125e-6],
            nx: 100,
            left: Side::Mirror,
            right: Side::FreeSlip,
            bottom: Side::NoSlip,
            top: Side::FreeSlip,
        },
        kernel: KernelCfg { kind: KernelKind::Quintic, h_ratio: 1.0 },
        phases: vec![
            // p_b = B of water in both phases (the impact is dominated by inertia, We = 6.86;
            // not re-tuned by the capillary rule of the equal-density scenes).
            Phase { p_b: b, ..fluid("water", 1000.0, 1.136e-3, 20.0, 7.0) },
            Phase { p_b: b, ..fluid("air", 1.2, 1.8e-5, c_air, 1.4) },
        ],
        fill: "air".into(),
        shapes: vec![Shape::circle([0.0, 375e-6], 250e-6, "water", [0.0, -1.0])],
        surface_tension: Some(SurfaceTension::thesis(0.0729)),
        contact: Contact {
            mode: ContactMode::B,
            sigma_ls: 0.0,
            sigma_gs: 0.0,
            theta_deg,
            normal_correction: true,
            wall_typing: true,
            band: 1.2,
        },
        walls: Walls { pressure: WallPressure::RWall, ..Walls::default() },
        gravity: [0.0, -9.8],
        time: adaptive_time(1.65e-3),
        relax: None,
        initial_velocity: None,
        interface_wave: None,
        output: Output { every: 2000 },
    }
}

/// Single-phase plane Poiseuille flow between no-slip plates y = 0 and y = 1, periodic in x,
/// driven by a body force g_x = 8 (ρ = 1, μ = 1 ⇒ steady u_max = 1). Analytic transient
/// solution in `diagnostics::poiseuille_velocity` (Morris et al. 1997).
pub fn poiseuille() -> Scene {
    Scene {
        name: "poiseuille".into(),
        description:
            "Single phase: body-force-driven Poiseuille flow between no-slip plates, periodic ends (Morris 1997)".into(),
        domain: Domain {
            x: [0.0, 0.4],
            y: [0.0, 1.0],
            nx: 8,
            left: Side::Periodic,
            right: Side::Periodic,
            bottom: Side::NoSlip,
            top: Side::NoSlip,
        },
        kernel: KernelCfg { kind: KernelKind::Quintic, h_ratio: 1.0 },
        phases: vec![fluid("fluid", 1.0, 1.0, 10.0, 7.0)],
        fill: "fluid".into(),
        shapes: vec![],
        surface_tension: None,
        contact: Contact::default(),
        walls: Walls::default(),
        gravity: [8.0, 0.0],
        time: adaptive_time(1.0),
        relax: None,
        initial_velocity: None,
        interface_wave: None,
        output: Output { every: 100 },
    }
}

/// Wavelength of the capillary-wave scenes.
pub const WAVE_LAMBDA: f64 = 1.0;
/// Initial amplitude of the capillary-wave scenes, a0 = 0.01λ (ka0 = 0.063).
pub const WAVE_A0: f64 = 0.01;
/// Laplace number σρ_Lλ/μ_L² of the capillary-wave scenes (Popinet's 2009 capillary-wave test).
pub const WAVE_LAPLACE: f64 = 3000.0;

/// §9(f): Prosperetti's standing capillary wave, one wavelength λ = 1 periodic in x, the lower
/// fluid ("liquid", ρ = 1) and the upper ("gas", ρ = 1/`density_ratio`) each λ/2 deep to a
/// mirror (coth(kH) − 1 = 0.0075: ω0 0.19 % below deep water). σ = 1, equal kinematic
/// viscosities with La = 3000; interface y = 0.01 cos(2πx) at rest; 44 × 44 particles
/// (Δx = λ/44). Equal densities: c0 = 20, γ = 7 in both. Density ratio 1000: one stiffness B
/// in both phases (docs/PHYSICS.md §3), the light phase air-like, γ = 1.4,
/// c = (1.4B/ρ_G)^{1/2}. p_b = σ/(2Δx) in both (the two-phase rule,
/// [`capillary_background_pressure`]). Runs 4 inviscid periods (density ratio 1000: 3).
pub fn capillary_wave(density_ratio: f64) -> Scene {
    let nx = 44;
    let dx = WAVE_LAMBDA / nx as f64;
    let (rho_g, c_l, gamma_l) = (1.0 / density_ratio, 20.0, 7.0);
    let mu_l = (WAVE_LAMBDA / WAVE_LAPLACE).sqrt();
    let b = 1.0 * c_l * c_l / gamma_l;
    let gamma_g = if density_ratio == 1.0 { gamma_l } else { 1.4 };
    let p_b = capillary_background_pressure(1.0, dx);
    let omega0 = ((2.0 * std::f64::consts::PI / WAVE_LAMBDA).powi(3) / (1.0 + rho_g)).sqrt();
    let periods = if density_ratio == 1.0 { 4.0 } else { 3.0 };
    let t_end = (periods * 2.0 * std::f64::consts::PI / omega0 * 100.0).ceil() / 100.0;
    let (name, what) = if density_ratio == 1.0 {
        ("capillary-wave".to_string(), "equal densities".to_string())
    } else {
        (format!("capillary-wave-{density_ratio}"), format!("density ratio {density_ratio}"))
    };
    Scene {
        name,
        description: format!(
            "Prosperetti 1981: standing capillary wave, {what}, equal kinematic viscosities (La = 3000), a0 = 0.01λ"
        ),
        domain: Domain {
            x: [0.0, WAVE_LAMBDA],
            y: [-0.5 * WAVE_LAMBDA, 0.5 * WAVE_LAMBDA],
            nx,
            left: Side::Periodic,
            right: Side::Periodic,
            bottom: Side::Mirror,
            top: Side::Mirror,
        },
        kernel: KernelCfg { kind: KernelKind::Quintic, h_ratio: 1.2 },
        phases: vec![
            Phase { p_b, ..fluid("liquid", 1.0, mu_l, c_l, gamma_l) },
            Phase { p_b, ..fluid("gas", rho_g, mu_l * rho_g, (gamma_g * b / rho_g).sqrt(), gamma_g) },
        ],
        fill: "gas".into(),
        shapes: vec![Shape {
            kind: ShapeKind::Rect,
            centre: None,
            radius: None,
            min: Some([0.0, -0.5 * WAVE_LAMBDA]),
            max: Some([WAVE_LAMBDA, 0.0]),
            phase: "liquid".into(),
            velocity: [0.0, 0.0],
        }],
        surface_tension: Some(SurfaceTension::thesis(1.0)),
        contact: Contact::default(),
        walls: Walls::default(),
        gravity: [0.0, 0.0],
        time: adaptive_time(t_end),
        relax: None,
        initial_velocity: None,
        interface_wave: Some(InterfaceWave { y0: 0.0, amplitude: WAVE_A0, wavelength: WAVE_LAMBDA }),
        output: Output { every: if density_ratio == 1.0 { 20 } else { 200 } },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_moving_contact_rule_is_fixed_in_capillary_units_until_the_interface_floor_binds() {
        let pb = |nx: f64| moving_contact_background_pressure(1.0, 0.25, 0.5 / nx);
        // 45 at the convergence case's 0.5/45, 65 and 85 (the value σ/(2Δx) takes at 0.5/45) ...
        for nx in [45.0, 65.0, 85.0] {
            assert!((pb(nx) - 45.0).abs() < 1e-12, "nx {nx}: {}", pb(nx));
        }
        assert_eq!(pb(45.0), capillary_background_pressure(1.0, 0.5 / 45.0));
        // ... and the band's tensile stress 0.2314σ/Δx once that is larger (from nx ≈ 97.2).
        assert!((pb(105.0) - 0.2314 * 210.0).abs() < 1e-9, "{}", pb(105.0));
        assert!(pb(97.0) == 45.0 && pb(98.0) > 45.0);
        // In units of σ/R: a smaller drop at the same Δx takes a proportionally larger p_b.
        assert!((moving_contact_background_pressure(2.0, 0.125, 0.5 / 65.0) - 180.0).abs() < 1e-12);
        assert_eq!(relax_60().phases[0].p_b, pb(65.0));
        assert_eq!(relax_60().phases[1].p_b, pb(65.0));
    }
}
