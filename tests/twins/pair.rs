//! Twin checks of `pair.wgsl` (part of `tests/wgsl_twins.rs`; same harness, error measure and
//! tolerances, see its module doc).

use super::{check, m, mv, v2, N, TOL32, TOL64};
use crate::common::{Case, Rng, Twin};
use sphlab::gpu::GpuContext;
use sphlab::physics::pair;
use sphlab::real::{Real, Sym2, V2};

// ---------------------------------------------------------------------------------------------
// pair.wgsl

pub fn rand_vec<T: Real>(rng: &mut Rng, lo: f64, hi: f64) -> Vec<T> {
    vec![rng.signed_log(lo, hi), rng.signed_log(lo, hi)]
}

pub fn pair_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0x9a1e);
    let tol = (TOL32, TOL64);
    let pair = |name, body, nout| Twin { name, module: "pair", body, nout };
    let vabs = |v: V2<T>| V2::new(v.x.abs(), v.y.abs());

    // grad_w_ij(dwdr, x_ij, r): r = |x_ij|, edge x_ij = 0 (r = 0) and dwdr = 0.
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let x: Vec<T> = if k == 0 { vec![T::zero(); 2] } else { rand_vec(&mut rng, 1e-5, 0.03) };
            let r = V2::new(x[0], x[1]).norm();
            let dwdr = if k == 1 { T::zero() } else { -rng.signed_log::<T>(1e-2, 1e6).abs() };
            Case::new(vec![dwdr, x[0], x[1], r], vec![])
        })
        .collect();
    check(ctx, pair("grad_w_ij", "put2(i, 0u, grad_w_ij(a(i, 0u), a2(i, 1u), a(i, 3u)));", 2), &cases, tol, |c| {
        let g = pair::grad_w_ij(c.args[0], v2(c, 1), c.args[3]);
        mv(g, g).to_vec()
    });
    let grads = cases.clone();

    // pressure_acc_ij(p_i, inv_s2_i, p_j, inv_s2_j, grad_w): p of either sign (cancellation).
    let cases: Vec<Case<T>> = grads
        .iter()
        .map(|g| {
            let g = pair::grad_w_ij(g.args[0], v2(g, 1), g.args[3]);
            let p = |r: &mut Rng| r.signed_log::<T>(1e-2, 1e5);
            let s = |r: &mut Rng| r.signed_log::<T>(1e2, 1e8).abs();
            Case::new(vec![p(&mut rng), s(&mut rng), p(&mut rng), s(&mut rng), g.x, g.y], vec![])
        })
        .collect();
    let body = "put2(i, 0u, pressure_acc_ij(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u), a2(i, 4u)));";
    check(ctx, pair("pressure_acc_ij", body, 2), &cases, tol, |c| {
        let [pi, si, pj, sj] = [0, 1, 2, 3].map(|k| c.args[k]);
        let g = v2(c, 4);
        mv(pair::pressure_acc_ij(pi, si, pj, sj, g), vabs(g) * ((pi * si).abs() + (pj * sj).abs())).to_vec()
    });

    // harmonic_viscosity(eta_i, eta_j): edges (0, 0) → 0 and (0, η).
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let e = |r: &mut Rng| r.signed_log::<T>(1e-6, 10.0).abs();
            let (a, b) = (e(&mut rng), e(&mut rng));
            Case::new(vec![if k < 2 { T::zero() } else { a }, if k == 0 { T::zero() } else { b }], vec![])
        })
        .collect();
    check(
        ctx,
        pair("harmonic_viscosity", "put(i, 0u, harmonic_viscosity(a(i, 0u), a(i, 1u)));", 1),
        &cases,
        tol,
        |c| vec![m(pair::harmonic_viscosity(c.args[0], c.args[1]))],
    );

    // inv_sigma2(σ): number densities from a coarse to a fine lattice (1/Δx² for Δx in
    // [1e-4, 1]), where 1/σ² stays a normal float.
    let cases: Vec<Case<T>> = (0..N).map(|_| Case::new(vec![rng.signed_log::<T>(1.0, 1e8).abs()], vec![])).collect();
    check(ctx, pair("inv_sigma2", "put(i, 0u, inv_sigma2(a(i, 0u)));", 1), &cases, tol, |c| {
        vec![m(pair::inv_sigma2(c.args[0]))]
    });

    // viscous_fac_ij(dwdr, r, h): r in [0, 3h], edge r = 0.
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let h = rng.signed_log::<f64>(1e-3, 1e-1).abs();
            let r = if k == 0 { 0.0 } else { h * rng.range::<f64>(0.0, 3.0) };
            Case::new(vec![-rng.signed_log::<T>(1e-2, 1e6).abs(), T::c(r), T::c(h)], vec![])
        })
        .collect();
    check(
        ctx,
        pair("viscous_fac_ij", "put(i, 0u, viscous_fac_ij(a(i, 0u), a(i, 1u), a(i, 2u)));", 1),
        &cases,
        tol,
        |c| vec![m(pair::viscous_fac_ij(c.args[0], c.args[1], c.args[2]))],
    );
    let facs: Vec<T> = cases.iter().map(|c| pair::viscous_fac_ij(c.args[0], c.args[1], c.args[2])).collect();

    // viscous_acc_ij(eta_ij, inv_s2_i, inv_s2_j, fac, v_ij).
    let cases: Vec<Case<T>> = facs
        .iter()
        .map(|&fac| {
            let pos = |r: &mut Rng, lo, hi| r.signed_log::<T>(lo, hi).abs();
            let v = rand_vec::<T>(&mut rng, 1e-4, 10.0);
            Case::new(
                vec![pos(&mut rng, 1e-6, 1.0), pos(&mut rng, 1e2, 1e8), pos(&mut rng, 1e2, 1e8), fac, v[0], v[1]],
                vec![],
            )
        })
        .collect();
    let body = "put2(i, 0u, viscous_acc_ij(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u), a2(i, 4u)));";
    check(ctx, pair("viscous_acc_ij", body, 2), &cases, tol, |c| {
        let a = pair::viscous_acc_ij(c.args[0], c.args[1], c.args[2], c.args[3], v2(c, 4));
        mv(a, a).to_vec()
    });

    // viscous_projected_acc_ij(eta_ij, inv_s2_i, inv_s2_j, fac, v_ij, x_ij, r2): the same
    // cases with a pair vector x_ij and r2 = |x_ij|²; edge x_ij = 0 (r2 = 0 → zero).
    let cases: Vec<Case<T>> = cases
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let x: Vec<T> = if k == 0 { vec![T::zero(); 2] } else { rand_vec(&mut rng, 1e-5, 0.03) };
            let r2 = x[0] * x[0] + x[1] * x[1];
            let mut args = c.args.clone();
            args.extend([x[0], x[1], r2]);
            Case::new(args, vec![])
        })
        .collect();
    let body = "put2(i, 0u, viscous_projected_acc_ij(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u), a2(i, 4u), a2(i, 6u), a(i, 8u)));";
    check(ctx, pair("viscous_projected_acc_ij", body, 2), &cases, tol, |c| {
        let a = |k: usize| c.args[k];
        let (v, x) = (v2(c, 4), v2(c, 6));
        let got = pair::viscous_projected_acc_ij(a(0), a(1), a(2), a(3), v, x, a(8));
        // Magnitude without the cancellation of v·x: |η(…)·fac·4| (|v_x x_x| + |v_y x_y|) |x| / r².
        let s = if a(8) > T::zero() {
            (a(0) * (a(1) + a(2)) * a(3) * T::c(4.0)).abs() * ((v.x * x.x).abs() + (v.y * x.y).abs()) / a(8)
        } else {
            T::zero()
        };
        mv(got, V2::new(x.x.abs() * s, x.y.abs() * s)).to_vec()
    });

    // colour_gradient_ij(inv_s2_j, grad_w), surface_acc_ij(Π_i, s_i, Π_j, s_j, grad_w).
    let cases: Vec<Case<T>> = grads
        .iter()
        .map(|g| {
            let g = pair::grad_w_ij(g.args[0], v2(g, 1), g.args[3]);
            let s = |r: &mut Rng| r.signed_log::<T>(1e2, 1e8).abs();
            let pi = |r: &mut Rng| r.signed_log::<T>(1e-6, 1e2);
            let a = vec![pi(&mut rng), pi(&mut rng), s(&mut rng), pi(&mut rng), pi(&mut rng), s(&mut rng), g.x, g.y];
            Case::new(a, vec![])
        })
        .collect();
    check(
        ctx,
        pair("colour_gradient_ij", "put2(i, 0u, colour_gradient_ij(a(i, 2u), a2(i, 6u)));", 2),
        &cases,
        tol,
        |c| {
            let g = pair::colour_gradient_ij(c.args[2], v2(c, 6));
            mv(g, g).to_vec()
        },
    );
    // colour_gradient_single_ij(c_i, inv_s2_i, c_j, inv_s2_j, grad_w): colours 0/1 in every
    // combination (the args 0 and 3 reused as colours by their sign).
    let body = "put2(i, 0u, colour_gradient_single_ij(a(i, 0u), a(i, 2u), a(i, 3u), a(i, 5u), a2(i, 6u)));";
    let single: Vec<Case<T>> = cases
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let mut a = c.args.clone();
            a[0] = if k % 2 == 0 { T::one() } else { T::zero() };
            a[3] = if (k / 2) % 2 == 0 { T::one() } else { T::zero() };
            Case::new(a, vec![])
        })
        .collect();
    check(ctx, pair("colour_gradient_single_ij", body, 2), &single, tol, |c| {
        let a = |k: usize| c.args[k];
        let g = v2(c, 6);
        let mag = vabs(g) * ((a(0) * a(2)).abs() + (a(3) * a(5)).abs());
        mv(pair::colour_gradient_single_ij(a(0), a(2), a(3), a(5), g), mag).to_vec()
    });
    let body = "put2(i, 0u, surface_acc_ij(Sym2(a(i, 0u), a(i, 1u)), a(i, 2u), Sym2(a(i, 3u), a(i, 4u)), a(i, 5u), a2(i, 6u)));";
    check(ctx, pair("surface_acc_ij", body, 2), &cases, tol, |c| {
        let a = |k: usize| c.args[k];
        let (pi, pj) = (Sym2 { xx: a(0), xy: a(1) }, Sym2 { xx: a(3), xy: a(4) });
        let g = v2(c, 6);
        let xx = (pi.xx * a(2)).abs() + (pj.xx * a(5)).abs();
        let xy = (pi.xy * a(2)).abs() + (pj.xy * a(5)).abs();
        let mag = V2::new(xx * g.x.abs() + xy * g.y.abs(), xy * g.x.abs() + xx * g.y.abs());
        mv(pair::surface_acc_ij(pi, a(2), pj, a(5), g), mag).to_vec()
    });

    // xsph_ij(m_j, rho_i, rho_j, v_ji, w): w = 0 edge.
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let pos = |r: &mut Rng, lo, hi| r.signed_log::<T>(lo, hi).abs();
            let v = rand_vec::<T>(&mut rng, 1e-4, 10.0);
            let w = if k == 0 { T::zero() } else { pos(&mut rng, 1e-3, 1e5) };
            Case::new(
                vec![pos(&mut rng, 1e-6, 1.0), pos(&mut rng, 0.5, 2e3), pos(&mut rng, 0.5, 2e3), v[0], v[1], w],
                vec![],
            )
        })
        .collect();
    let body = "put2(i, 0u, xsph_ij(a(i, 0u), a(i, 1u), a(i, 2u), a2(i, 3u), a(i, 5u)));";
    check(ctx, pair("xsph_ij", body, 2), &cases, tol, |c| {
        let x = pair::xsph_ij(c.args[0], c.args[1], c.args[2], v2(c, 3), c.args[5]);
        mv(x, x).to_vec()
    });
}
