//! Ladder step 2 (GPU): every WGSL function of `shaders/` against its Rust twin in
//! `core/src/physics/` (wgebra pattern: compose the module plus an appended `@compute` test kernel,
//! run thousands of seeded random inputs plus the edge cases, outputs poisoned with NaN first).
//!
//! Error measure (see `common::compare`): `|gpu − cpu| / max(magnitude, floor)`, where
//! `magnitude` is the sum of the absolute values of the terms that cancel in the formula (|cpu|
//! when nothing cancels), i.e. the scale of the rounding error any correct evaluation commits.
//!
//! Tolerances. f32: [`TOL32`] = 2e-6 ≈ 17 ulp of the magnitude. The WGSL does the same
//! operations in the same order as Rust, but Vulkan grants 2.5 ulp to `/` and `sqrt`, the
//! driver may contract `a*b + c` into an FMA (one rounding fewer), and these differences add
//! over the ≤ 10 operations of a function. `exp` (Gaussian kernel) is granted 3 + 2|x| ulp by
//! Vulkan, up to 21 ulp at q = 3, hence [`TOL32_EXP`]; `pow` (non-integer γ) and `sin`/`cos`
//! are looser in the Vulkan spec still, hence their own tolerances. f64: [`TOL64`] = 1e-12
//! (≈ 4500 ulp, far below any physical effect yet far above FMA/division differences), except
//! where the f64 build calls f32 `exp`/`pow`/`sin`/`cos` (GLSL.std.450 has no f64 versions):
//! there the f32 accuracy applies. The absolute floor 1e-30 (f32) / 1e-300 (f64) ignores
//! flushed denormals (Vulkan allows flush-to-zero).

mod common;

use common::{compare, gpu_or_skip, run_twin, serial, Case, Rng, Twin};
use sphlab::gpu::GpuContext;
use sphlab::physics::kernel::{KernelKind, KernelParams};
use sphlab::physics::{eos, kernel};
use sphlab::real::{Real, V2};

/// f32 tolerance of exactly-rounded arithmetic chains (see module doc).
const TOL32: f64 = 2e-6;
/// f32 tolerance where `exp` is involved.
const TOL32_EXP: f64 = 5e-6;
/// f32 tolerance for `pow` with a non-integer exponent and for `sin`/`cos` (absolute).
const TOL32_TRANSC: f64 = 1e-5;
/// f64 tolerance.
const TOL64: f64 = 1e-12;
/// f64 builds that call f32 `exp`/`pow`/`sin`/`cos`.
const TOL64_VIA_F32: f64 = 2e-6;
/// Random cases per function (plus edge cases).
const N: usize = 4096;

fn is64<T: Real>() -> bool {
    T::NAME == "f64"
}

/// Runs the twin, compares with `cpu` (which returns `(value, magnitude)` per output).
fn check<T: Real>(
    ctx: &GpuContext,
    t: Twin,
    cases: &[Case<T>],
    tol: (f64, f64),
    cpu: impl Fn(&Case<T>) -> Vec<(T, T)>,
) -> f64 {
    let gpu = run_twin(ctx, &t, cases);
    let want: Vec<(T, T)> = cases
        .iter()
        .flat_map(|c| {
            let o = cpu(c);
            assert_eq!(o.len(), t.nout, "{}: CPU output arity", t.name);
            o
        })
        .collect();
    let (tol, floor) = if is64::<T>() { (tol.1, 1e-300) } else { (tol.0, 1e-30) };
    compare(t.name, &gpu, &want, cases, tol, floor)
}

/// |x| as a magnitude.
fn m<T: Real>(x: T) -> (T, T) {
    (x, x.abs())
}

/// Vector output with per-component magnitudes.
fn mv<T: Real>(v: V2<T>, mag: V2<T>) -> [(T, T); 2] {
    [(v.x, mag.x.abs()), (v.y, mag.y.abs())]
}

fn v2<T: Real>(c: &Case<T>, k: usize) -> V2<T> {
    V2::new(c.args[k], c.args[k + 1])
}

fn next<T: Real>(x: f64, up: bool) -> T {
    if is64::<T>() {
        T::c(if up { x.next_up() } else { x.next_down() })
    } else {
        let x = x as f32;
        T::c(if up { x.next_up() } else { x.next_down() } as f64)
    }
}

fn with_gpu<T: Real>(f: fn(&GpuContext)) {
    let _guard = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if is64::<T>() && !ctx.has(wgpu::Features::SHADER_F64) {
        let msg = format!("\n!!!!!!!! SKIP f64 twins: adapter lacks SHADER_F64 ({}) !!!!!!!!\n", ctx.describe());
        let _ = std::io::Write::write_all(&mut std::io::stderr(), msg.as_bytes()); // not captured
        return;
    }
    f(&ctx);
}

macro_rules! twin_tests {
    ($($body:ident => $t32:ident, $t64:ident;)*) => {$(
        #[test]
        fn $t32() {
            with_gpu::<f32>($body::<f32>);
        }
        #[test]
        fn $t64() {
            with_gpu::<f64>($body::<f64>);
        }
    )*};
}

twin_tests! {
    kernel_twins => kernel_f32, kernel_f64;
    eos_twins => eos_f32, eos_f64;
    pair_twins => pair_f32, pair_f64;
    stress_twins => stress_f32, stress_f64;
    wall_twins => wall_f32, wall_f64;
    contact_twins => contact_f32, contact_f64;
    integrate_twins => integrate_f32, integrate_f64;
    boundary_twins => boundary_f32, boundary_f64;
    timestep_twins => timestep_f32, timestep_f64;
}

// ---------------------------------------------------------------------------------------------
// kernel.wgsl

/// Magnitude of f(q): the sum of |terms| (the quintic's three powers cancel strongly).
fn kernel_f_mag(kind: KernelKind, q: f64) -> f64 {
    let p5 = |a: f64| a.powi(5);
    match kind {
        KernelKind::CubicSpline if q < 1.0 => 1.0 + 1.5 * q * q + 0.75 * q * q * q,
        KernelKind::Quintic if q < 1.0 => p5(3.0 - q) + 6.0 * p5(2.0 - q) + 15.0 * p5(1.0 - q),
        KernelKind::Quintic if q < 2.0 => p5(3.0 - q) + 6.0 * p5(2.0 - q),
        _ => kernel::kernel_f(kind, q).abs(),
    }
}

/// Magnitude of f'(q) (at q → 0 the quintic's −405 + 480 − 75 cancel exactly).
fn kernel_df_mag(kind: KernelKind, q: f64) -> f64 {
    let p4 = |a: f64| a.powi(4);
    match kind {
        KernelKind::CubicSpline if q < 1.0 => 3.0 * q + 2.25 * q * q,
        KernelKind::Quintic if q < 1.0 => 5.0 * p4(3.0 - q) + 30.0 * p4(2.0 - q) + 75.0 * p4(1.0 - q),
        KernelKind::Quintic if q < 2.0 => 5.0 * p4(3.0 - q) + 30.0 * p4(2.0 - q),
        _ => kernel::kernel_df(kind, q).abs(),
    }
}

/// q samples: knots 0, 1, 2, 3 and their neighbours, just past the support, tiny and
/// denormal values, then uniform over [0, κ + 0.5].
fn q_samples<T: Real>(rng: &mut Rng, kind: KernelKind) -> Vec<T> {
    let kappa = kind.support_factor();
    let mut q: Vec<T> = vec![T::zero(), T::c(1e-30), T::c(1e-7), T::c(kappa + 1e-3), T::c(kappa + 0.5)];
    for knot in [1.0, 2.0, 3.0] {
        q.extend([T::c(knot), next(knot, true), next(knot, false)]);
    }
    if !is64::<T>() {
        q.push(T::c(f32::from_bits(1) as f64)); // smallest f32 denormal
    }
    q.extend((0..N).map(|_| rng.range::<T>(0.0, kappa + 0.5)));
    q
}

fn kernel_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0x5e4_1ab);
    let exp_tol = (TOL32_EXP, TOL64_VIA_F32);
    for kind in KernelKind::ALL {
        let tol = if kind == KernelKind::Gaussian { exp_tol } else { (TOL32, TOL64) };
        let cases: Vec<Case<T>> =
            q_samples::<T>(&mut rng, kind).into_iter().map(|q| Case::new(vec![q], vec![kind.id()])).collect();
        let label = |f: &str| format!("{f}[{}]", kind.name());
        let body_f = "put(i, 0u, kernel_f(n(i, 0u), a(i, 0u)));";
        check(ctx, Twin { name: &label("kernel_f"), module: "kernel", body: body_f, nout: 1 }, &cases, tol, |c| {
            vec![(kernel::kernel_f(kind, c.args[0]), T::c(kernel_f_mag(kind, c.args[0].f64())))]
        });
        let body_df = "put(i, 0u, kernel_df(n(i, 0u), a(i, 0u)));";
        check(ctx, Twin { name: &label("kernel_df"), module: "kernel", body: body_df, nout: 1 }, &cases, tol, |c| {
            vec![(kernel::kernel_df(kind, c.args[0]), T::c(kernel_df_mag(kind, c.args[0].f64())))]
        });
        // W and ∂W/∂r: h log-uniform in [1e-3, 1], r = q h plus r = 0, h, 2h, 3h, support, past it.
        let mut cases = Vec::new();
        for k in 0..N {
            let h = rng.signed_log::<f64>(1e-3, 1.0).abs();
            let kp = KernelParams::<T>::new(kind, h);
            let r = match k {
                0 => T::zero(),
                1..=3 => kp.h * T::c(k as f64),
                4 => kp.support,
                5 => next(kp.support.f64(), true),
                _ => kp.h * rng.range::<T>(0.0, kind.support_factor() + 0.5),
            };
            cases.push(Case::new(vec![kp.h, kp.inv_h, kp.alpha, kp.support, r], vec![kind.id()]));
        }
        let params =
            |c: &Case<T>| KernelParams { kind, h: c.args[0], inv_h: c.args[1], alpha: c.args[2], support: c.args[3] };
        let q = |c: &Case<T>| (c.args[4] * c.args[1]).f64();
        let kp = "KernelParams(n(i, 0u), a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u))";
        let body_w = format!("put(i, 0u, kernel_w({kp}, a(i, 4u)));");
        check(ctx, Twin { name: &label("kernel_w"), module: "kernel", body: &body_w, nout: 1 }, &cases, tol, |c| {
            let p = params(c);
            vec![(kernel::kernel_w(&p, c.args[4]), T::c(p.alpha.f64() * kernel_f_mag(kind, q(c))))]
        });
        let body_dw = format!("put(i, 0u, kernel_dwdr({kp}, a(i, 4u)));");
        check(ctx, Twin { name: &label("kernel_dwdr"), module: "kernel", body: &body_dw, nout: 1 }, &cases, tol, |c| {
            let p = params(c);
            let mag = p.alpha.f64() * p.inv_h.f64() * kernel_df_mag(kind, q(c));
            vec![(kernel::kernel_dwdr(&p, c.args[4]), T::c(mag))]
        });
    }
}

// ---------------------------------------------------------------------------------------------
// eos.wgsl

fn eos_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0xe05);
    let body = "put(i, 0u, eos_pressure(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u), a(i, 4u)));";
    // Whole γ (repeated multiplication on the GPU) and non-integer γ (pow, f32 in f64 builds).
    for (gammas, tol) in
        [(&[7.0, 1.0, 2.0, 3.0][..], (TOL32, TOL64)), (&[1.4, 2.5, 7.5][..], (TOL32_TRANSC, TOL64_VIA_F32))]
    {
        let cases: Vec<Case<T>> = (0..N)
            .map(|k| {
                let gamma = gammas[k % gammas.len()];
                let rho0 = rng.range::<f64>(1.0, 1500.0);
                let b = eos::eos_stiffness(rho0, rng.range::<f64>(1.0, 50.0), gamma);
                let rho = if k < 8 { rho0 } else { rho0 * rng.range::<f64>(0.8, 1.2) };
                let p_b = if k % 3 == 0 { 0.0 } else { rng.range::<f64>(0.0, 0.1 * b) };
                Case::new(vec![T::c(rho), T::c(rho0), T::c(b), T::c(gamma), T::c(p_b)], vec![])
            })
            .collect();
        check(ctx, Twin { name: "eos_pressure", module: "eos", body, nout: 1 }, &cases, tol, |c| {
            let [rho, rho0, b, gamma, p_b] = [0, 1, 2, 3, 4].map(|k| c.args[k]);
            let mag = b.f64() * ((rho / rho0).f64().powf(gamma.f64()) + 1.0) + p_b.f64().abs();
            vec![(eos::eos_pressure(rho, rho0, b, gamma, p_b), T::c(mag))]
        });
    }
}

/// The harness itself: an unwritten output keeps its NaN poison and fails the comparison, and
/// a wrong value fails while a rounding-level one passes.
#[test]
fn harness_catches_unwritten_and_wrong_outputs() {
    let _guard = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let cases: Vec<Case<f32>> = (0..100).map(|k| Case::new(vec![k as f32 + 1.0], vec![])).collect();
    let t = Twin { name: "harness", module: "kernel", body: "if i != 37u { put(i, 0u, a(i, 0u)); }", nout: 1 };
    let gpu = run_twin(&ctx, &t, &cases);
    assert!(gpu[37].is_nan() && gpu[36] == 37.0, "element 37 unwritten, the others copied");
    let exact: Vec<(f32, f32)> = cases.iter().map(|c| (c.args[0], c.args[0])).collect();
    let poisoned = std::panic::catch_unwind(|| compare("harness", &gpu, &exact, &cases, TOL32, 1e-30));
    assert!(poisoned.is_err(), "a NaN left by an unwritten element must fail");
    let mut good = gpu.clone();
    good[37] = 38.0 * (1.0 + f32::EPSILON);
    assert!(compare("harness", &good, &exact, &cases, TOL32, 1e-30) < TOL32, "one ulp passes");
    good[37] = 38.001;
    let wrong = std::panic::catch_unwind(|| compare("harness", &good, &exact, &cases, TOL32, 1e-30));
    assert!(wrong.is_err(), "a 3e-5 relative error must fail");
}

// pair.wgsl, stress.wgsl, wall.wgsl, contact.wgsl, integrate.wgsl, geometry.wgsl and timestep.wgsl (kept apart
// to keep files short).
#[path = "twins/boundary.rs"]
mod boundary;
#[path = "twins/geometry.rs"]
mod geometry;
#[path = "twins/pair.rs"]
mod pair_checks;
#[path = "twins/timestep.rs"]
mod timestep;
use boundary::boundary_twins;
use geometry::{contact_twins, integrate_twins, stress_twins, wall_twins};
use pair_checks::{pair_twins, rand_vec};
use timestep::timestep_twins;
