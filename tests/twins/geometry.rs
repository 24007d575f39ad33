//! Twin checks of `stress.wgsl`, `wall.wgsl`, `contact.wgsl` and `integrate.wgsl` (part of
//! `tests/wgsl_twins.rs`; same harness, error measure and tolerances, see its module doc).

use super::{check, m, mv, rand_vec, v2, N, TOL32, TOL32_TRANSC, TOL64, TOL64_VIA_F32};
use crate::common::{Case, Rng, Twin};
use sphlab::gpu::GpuContext;
use sphlab::physics::{contact, integrate, stress, wall};
use sphlab::real::{Real, Sym2, V2};

pub fn stress_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0x57e55);
    let tol = (TOL32, TOL64);
    // stress_tensor(g, σ): edges g = 0 (→ 0), one zero component, σ = 0.
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let mut g = rand_vec::<T>(&mut rng, 1e-3, 1e5);
            match k {
                0 => g = vec![T::zero(); 2],
                1 => g[0] = T::zero(),
                2 => g[1] = T::zero(),
                _ => {}
            }
            let sigma = if k == 3 { T::zero() } else { rng.range::<T>(0.0, 0.1) };
            Case::new(vec![g[0], g[1], sigma], vec![])
        })
        .collect();
    let body = "let s = stress_tensor(a2(i, 0u), a(i, 2u)); put(i, 0u, s.xx); put(i, 1u, s.xy);";
    check(ctx, Twin { name: "stress_tensor", module: "stress", body, nout: 2 }, &cases, tol, |c| {
        let g = v2(c, 0);
        let s = stress::stress_tensor(g, c.args[2]);
        let n = g.norm2();
        let mag_xx = if n > T::zero() { T::c(0.5) * n * c.args[2] / n.sqrt() } else { T::zero() };
        vec![(s.xx, mag_xx), m(s.xy)]
    });
    // sym2_mul_vec (the Sym2::mul_vec twin).
    let cases: Vec<Case<T>> = (0..N)
        .map(|_| {
            Case::new(
                rand_vec::<T>(&mut rng, 1e-3, 1e3).into_iter().chain(rand_vec(&mut rng, 1e-3, 1e3)).collect(),
                vec![],
            )
        })
        .collect();
    let body = "put2(i, 0u, sym2_mul_vec(Sym2(a(i, 0u), a(i, 1u)), a2(i, 2u)));";
    check(ctx, Twin { name: "sym2_mul_vec", module: "stress", body, nout: 2 }, &cases, tol, |c| {
        let (s, v) = (Sym2 { xx: c.args[0], xy: c.args[1] }, v2(c, 2));
        let mag = V2::new((s.xx * v.x).abs() + (s.xy * v.y).abs(), (s.xy * v.x).abs() + (s.xx * v.y).abs());
        mv(s.mul_vec(v), mag).to_vec()
    });
}

pub fn wall_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0xa11);
    let tol = (TOL32, TOL64);
    let wall = |name, body, nout| Twin { name, module: "wall", body, nout };
    // noslip_beta(d_i, d_j, β_max, Δx): edges d_j = 0, d_j < 0 (→ 1), d_i = 0 and d_i < 0 (floored).
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let dx = rng.signed_log::<f64>(1e-3, 1e-1).abs();
            let d_i = match k % 7 {
                0 => 0.0,
                1 => -0.3 * dx,
                _ => dx * rng.range::<f64>(0.0, 2.0),
            };
            let d_j = match k % 5 {
                0 => 0.0,
                1 => -dx * rng.range::<f64>(0.0, 1.0),
                _ => dx * rng.range::<f64>(0.0, 3.0),
            };
            Case::new(vec![T::c(d_i), T::c(d_j), rng.range(1.0, 3.0), T::c(dx)], vec![])
        })
        .collect();
    let body = "put(i, 0u, noslip_beta(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u)));";
    check(ctx, wall("noslip_beta", body, 1), &cases, tol, |c| {
        vec![m(wall::noslip_beta(c.args[0], c.args[1], c.args[2], c.args[3]))]
    });
    // wall_relative_velocity(v_i, β, free_slip, n_w): both branches, unit normals.
    let cases: Vec<Case<T>> = (0..N)
        .map(|_| {
            let v = rand_vec::<T>(&mut rng, 1e-4, 10.0);
            let th = rng.range::<f64>(0.0, std::f64::consts::TAU);
            Case::new(vec![v[0], v[1], rng.range(1.0, 3.0), T::c(th.cos()), T::c(th.sin())], vec![rng.bit()])
        })
        .collect();
    let body = "put2(i, 0u, wall_relative_velocity(a2(i, 0u), a(i, 2u), n(i, 0u) == 1u, a2(i, 3u)));";
    check(ctx, wall("wall_relative_velocity", body, 2), &cases, tol, |c| {
        let (v, beta, nw) = (v2(c, 0), c.args[2], v2(c, 3));
        let r = wall::wall_relative_velocity(v, beta, c.ints[0] == 1, nw);
        let dot_mag = (v.x * nw.x).abs() + (v.y * nw.y).abs();
        let mag = if c.ints[0] == 1 { V2::new(nw.x.abs(), nw.y.abs()) * (dot_mag * beta) } else { r };
        mv(r, mag).to_vec()
    });
    // holmes_beta(χ_i, χ_j, χ_floor, β_max): edges χ_j = ½ (→ 1), χ_i ≤ ½ (floored).
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let chi_j = if k % 6 == 0 { T::c(0.5) } else { rng.range(0.0, 1.0) };
            Case::new(vec![rng.range(0.0, 1.0), chi_j, rng.range(0.01, 0.1), rng.range(1.0, 3.0)], vec![])
        })
        .collect();
    let body = "put(i, 0u, holmes_beta(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u)));";
    check(ctx, wall("holmes_beta", body, 1), &cases, tol, |c| {
        vec![m(wall::holmes_beta(c.args[0], c.args[1], c.args[2], c.args[3]))]
    });
    // lj_wall_acc(r_ib, r0, D): |r| in (0, 1.2 r0], edges r = 0, r = r0 exactly, just inside.
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let r0 = rng.signed_log::<f64>(1e-3, 1e-1).abs();
            let th = rng.range::<f64>(0.0, std::f64::consts::TAU);
            let len = match k {
                0 => 0.0,
                1 | 2 => r0,
                _ => r0 * rng.range::<f64>(0.3, 1.2),
            };
            let r = if k == 1 { [r0, 0.0] } else { [len * th.cos(), len * th.sin()] };
            Case::new(vec![T::c(r[0]), T::c(r[1]), T::c(r0), rng.signed_log::<T>(1e-3, 10.0).abs()], vec![])
        })
        .collect();
    let body = "put2(i, 0u, lj_wall_acc(a2(i, 0u), a(i, 2u), a(i, 3u)));";
    check(ctx, wall("lj_wall_acc", body, 2), &cases, tol, |c| {
        let (r, r0, d) = (v2(c, 0), c.args[2], c.args[3]);
        let acc = wall::lj_wall_acc(r, r0, d);
        let r2 = r.norm2();
        // (r0/r)^12 and (r0/r)^4 cancel as r → r0: the magnitude is their sum.
        let mag = if r2 > T::zero() {
            let q2 = (r0 * r0 / r2).f64();
            let s = d.f64() * (q2.powi(6) + q2.powi(2)) / r2.f64();
            V2::new(T::c(r.x.f64().abs() * s), T::c(r.y.f64().abs() * s))
        } else {
            acc
        };
        mv(acc, mag).to_vec()
    });
}

pub fn contact_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0xc0);
    let contact = |name, body, nout| Twin { name, module: "contact", body, nout };
    // contact_normal(θ, s): sin/cos judged in absolute terms (components are bounded by 1).
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let th = match k {
                0 => 0.0,
                1 => std::f64::consts::FRAC_PI_2,
                2 => std::f64::consts::PI,
                _ => rng.range(0.0, std::f64::consts::PI),
            };
            Case::new(vec![T::c(th), T::c(if rng.bit() == 1 { 1.0 } else { -1.0 })], vec![])
        })
        .collect();
    let body = "put2(i, 0u, contact_normal(a(i, 0u), a(i, 1u)));";
    check(ctx, contact("contact_normal", body, 2), &cases, (TOL32_TRANSC, TOL64_VIA_F32), |c| {
        let nrm = contact::contact_normal(c.args[0], c.args[1]);
        vec![(nrm.x, T::one()), (nrm.y, T::one())]
    });
    let normals: Vec<V2<T>> = cases.iter().map(|c| contact::contact_normal(c.args[0], c.args[1])).collect();
    let tol = (TOL32, TOL64);
    // contact_side(r_w, r_tp, n̂_θ): the dot product cancels across the line.
    let cases: Vec<Case<T>> = normals
        .iter()
        .map(|nrm| {
            let (w, tp) = (rand_vec::<T>(&mut rng, 1e-4, 1.0), rand_vec::<T>(&mut rng, 1e-4, 1.0));
            Case::new(vec![w[0], w[1], tp[0], tp[1], nrm.x, nrm.y], vec![])
        })
        .collect();
    let body = "put(i, 0u, contact_side(a2(i, 0u), a2(i, 2u), a2(i, 4u)));";
    check(ctx, contact("contact_side", body, 1), &cases, tol, |c| {
        let (w, tp, nrm) = (v2(c, 0), v2(c, 2), v2(c, 4));
        let d = w - tp;
        vec![(contact::contact_side(w, tp, nrm), (d.x * nrm.x).abs() + (d.y * nrm.y).abs())]
    });
    // corrected_normal(g, n̂_θ, liquid): both signs, g = 0 edge.
    let cases: Vec<Case<T>> = normals
        .iter()
        .enumerate()
        .map(|(k, nrm)| {
            let g = if k == 0 { vec![T::zero(); 2] } else { rand_vec::<T>(&mut rng, 1e-3, 1e5) };
            Case::new(vec![g[0], g[1], nrm.x, nrm.y], vec![rng.bit()])
        })
        .collect();
    let body = "put2(i, 0u, corrected_normal(a2(i, 0u), a2(i, 2u), n(i, 0u) == 1u));";
    check(ctx, contact("corrected_normal", body, 2), &cases, tol, |c| {
        let r = contact::corrected_normal(v2(c, 0), v2(c, 2), c.ints[0] == 1);
        mv(r, r).to_vec()
    });
}

pub fn integrate_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0x1e7);
    let tol = (TOL32, TOL64);
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let mut a: Vec<T> = (0..4).flat_map(|_| rand_vec::<T>(&mut rng, 1e-4, 10.0)).collect();
            a.push(if k == 0 { T::zero() } else { rng.signed_log::<T>(1e-7, 1e-2).abs() });
            Case::new(a, vec![])
        })
        .collect();
    let vv = |c: &Case<T>| (v2(c, 0), v2(c, 2), v2(c, 4), v2(c, 6), c.args[8]);
    // x + y·s, magnitude |x| + |y·s| per component.
    let axpy = |x: V2<T>, y: V2<T>, s: T| {
        let r = x + y * s;
        mv(r, V2::new(x.x.abs() + (y.x * s).abs(), x.y.abs() + (y.y * s).abs()))
    };
    let it = |name, body, nout| Twin { name, module: "integrate", body, nout };
    let body = "let o = integrate_predict(a2(i, 0u), a2(i, 2u), a2(i, 4u), a2(i, 6u), a(i, 8u)); put2(i, 0u, o.r); put2(i, 2u, o.v);";
    check(ctx, it("integrate_predict", body, 4), &cases, tol, |c| {
        let (r, v, vt, a, dt) = vv(c);
        let (rs, vs) = integrate::integrate_predict(r, v, vt, a, dt);
        let half = T::c(0.5) * dt;
        let (mr, mvv) = (axpy(r, vt, half), axpy(v, a, half));
        assert_eq!((rs.x, vs.y), (mr[0].0, mvv[1].0), "twin of predict reproduced");
        [mr, mvv].concat()
    });
    let body = "let o = integrate_correct(a2(i, 0u), a2(i, 2u), a2(i, 4u), a2(i, 6u), a(i, 8u)); put2(i, 0u, o.r); put2(i, 2u, o.v);";
    check(ctx, it("integrate_correct", body, 4), &cases, tol, |c| {
        let (r, v, vt, a, dt) = vv(c);
        let (rs, vs) = integrate::integrate_correct(r, v, vt, a, dt);
        let (mr, mvv) = (axpy(r, vt, dt), axpy(v, a, dt));
        [mv(rs, V2::new(mr[0].1, mr[1].1)), mv(vs, V2::new(mvv[0].1, mvv[1].1))].concat()
    });
    let body = "put2(i, 0u, integrate_kick(a2(i, 2u), a2(i, 6u), a(i, 8u)));";
    check(ctx, it("integrate_kick", body, 2), &cases, tol, |c| {
        let (_, v, _, a, dt) = vv(c);
        let k = axpy(v, a, T::c(0.5) * dt);
        mv(integrate::integrate_kick(v, a, dt), V2::new(k[0].1, k[1].1)).to_vec()
    });
    let body = "put2(i, 0u, integrate_drift(a2(i, 0u), a2(i, 4u), a(i, 8u)));";
    check(ctx, it("integrate_drift", body, 2), &cases, tol, |c| {
        let (r, _, vt, _, dt) = vv(c);
        let d = axpy(r, vt, dt);
        mv(integrate::integrate_drift(r, vt, dt), V2::new(d[0].1, d[1].1)).to_vec()
    });
}
