//! Twin checks of `shaders/geometry.wgsl` (part of `tests/wgsl_twins.rs`; same harness, error
//! measure and tolerances, see its module doc): the image transforms against `model::Images`,
//! `wall_distance`/`wall_normal`/`nearest_wall` against `WallLine` and `Model::nearest_wall`,
//! `lennard_jones` against `cpu::momentum::lennard_jones`, `boundary_axis` against
//! `cpu::boundary_axis`. Each case is a random box whose four sides are each none, mirror or
//! periodic, up to four random wall lines, and a point inside, outside or near them.

use super::{check, m, v2, N, TOL32, TOL64};
use crate::common::{Case, Rng, Twin};
use sphlab::cpu::{boundary_axis, momentum::lennard_jones};
use sphlab::gpu::GpuContext;
use sphlab::model::{AxisMap, Images, Model, WallLine};
use sphlab::real::{Real, Sym2, V2};
use sphlab::scene::Scene;

/// Real arguments: image values 0–3, wall coords 4–7, wall signs 8–11, Δx 12, lo 13–14,
/// LJ strength 15, point 16–17, vector 18–19, tensor 20–21, hi 22–23.
/// Integer arguments: image kinds 0–3 (0 none, 1 mirror, 2 periodic), code 4, wall count 5,
/// wall axes 6–9.
const PARAMS: &str = "var prm: Params;
    prm.image_kind = vec4<u32>(n(i, 0u), n(i, 1u), n(i, 2u), n(i, 3u));
    prm.n_walls = n(i, 5u);
    prm.wall_axis = vec4<u32>(n(i, 6u), n(i, 7u), n(i, 8u), n(i, 9u));
    prm.image_value = vec4<real>(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u));
    prm.wall_coord = vec4<real>(a(i, 4u), a(i, 5u), a(i, 6u), a(i, 7u));
    prm.wall_sign = vec4<real>(a(i, 8u), a(i, 9u), a(i, 10u), a(i, 11u));
    prm.dx = a(i, 12u);
    prm.lo_x = a(i, 13u);
    prm.lo_y = a(i, 14u);
    prm.lj_strength = a(i, 15u);
    let c = n(i, 4u);
    let x = a2(i, 16u);";

/// One random geometry and point (see [`PARAMS`] for the layout).
fn geometry_case<T: Real>(rng: &mut Rng, k: usize) -> Case<T> {
    let lo = [rng.range::<f64>(-1.0, 1.0), rng.range::<f64>(-1.0, 1.0)];
    let len = [rng.range::<f64>(0.5, 2.0), rng.range::<f64>(0.5, 2.0)];
    let hi = [lo[0] + len[0], lo[1] + len[1]];
    let dx = rng.signed_log::<f64>(1e-2, 1e-1).abs();
    let mut kinds = [0u32; 4];
    let mut values = [0.0; 4];
    for side in 0..4 {
        let (axis, high) = (side / 2, side % 2 == 1);
        kinds[side] = (rng.next_u64() % 3) as u32;
        values[side] = match kinds[side] {
            1 => {
                if high {
                    hi[axis]
                } else {
                    lo[axis]
                }
            }
            2 => {
                if high {
                    len[axis]
                } else {
                    -len[axis]
                }
            }
            _ => 0.0,
        };
    }
    let n_walls = (rng.next_u64() % 5) as u32;
    let axes: Vec<u32> = (0..4).map(|_| rng.bit()).collect();
    let signs: Vec<f64> = (0..4).map(|_| if rng.bit() == 1 { 1.0 } else { -1.0 }).collect();
    let coords: Vec<f64> = (0..4)
        .map(|w| {
            let a = axes[w] as usize;
            (if signs[w] > 0.0 { lo[a] } else { hi[a] }) + rng.range::<f64>(-0.1, 0.1)
        })
        .collect();
    // The point: inside or outside the box (each side crossed), exactly on a side, or within
    // ±1.5 r0 of a wall line (inside and outside the LJ cut-off r0 = Δx/2).
    let mut x = [0, 1].map(|a| lo[a] + len[a] * rng.range::<f64>(-0.3, 1.3));
    match k % 8 {
        0 => x[0] = lo[0],
        1 => x[1] = hi[1],
        2..=4 if n_walls > 0 => {
            let w = (rng.next_u64() % n_walls as u64) as usize;
            x[axes[w] as usize] = coords[w] + signs[w] * 0.5 * dx * rng.range::<f64>(-0.5, 1.5);
        }
        _ => {}
    }
    let mut args: Vec<T> = values.iter().chain(&coords).chain(&signs).map(|&v| T::c(v)).collect();
    args.extend([dx, lo[0], lo[1], rng.signed_log::<f64>(1e-3, 10.0).abs(), x[0], x[1]].map(T::c));
    args.extend((0..4).map(|_| rng.signed_log::<T>(1e-3, 10.0)));
    args.extend([T::c(hi[0]), T::c(hi[1])]);
    let mut ints = kinds.to_vec();
    ints.extend([(rng.next_u64() % 9) as u32, n_walls]);
    ints.extend(axes);
    Case::new(args, ints)
}

fn axis_map<T: Real>(kind: u32, value: T) -> Option<AxisMap<T>> {
    match kind {
        1 => Some(AxisMap::Mirror(value)),
        2 => Some(AxisMap::Shift(value)),
        _ => None,
    }
}

/// The Rust side of one case: `base` with the case's images, walls, Δx, lo, hi and LJ strength.
fn model_of<T: Real>(base: &Model<T>, c: &Case<T>) -> Model<T> {
    let mut m = base.clone();
    let map = |s: usize| axis_map(c.ints[s], c.args[s]);
    m.images = Images { x: [map(0), map(1)], y: [map(2), map(3)] };
    m.walls = (0..c.ints[5] as usize)
        .map(|w| WallLine { axis: c.ints[6 + w] as usize, coord: c.args[4 + w], sign: c.args[8 + w], free_slip: false })
        .collect();
    (m.dx, m.lo, m.lj_strength, m.hi) = (c.args[12], v2(c, 13), c.args[15], v2(c, 22));
    m
}

/// Wall line w of a case (all four, whatever the wall count).
fn wall_of<T: Real>(c: &Case<T>, w: usize) -> WallLine<T> {
    WallLine { axis: c.ints[6 + w] as usize, coord: c.args[4 + w], sign: c.args[8 + w], free_slip: false }
}

pub fn boundary_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0x6e0);
    let tol = (TOL32, TOL64);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/pysph-rod.toml");
    let scene = Scene::from_toml(&std::fs::read_to_string(path).expect("scene file")).expect("valid scene");
    let base = Model::<T>::new(&scene);
    let cases: Vec<Case<T>> = (0..N).map(|k| geometry_case(&mut rng, k)).collect();
    let models: Vec<Model<T>> = cases.iter().map(|c| model_of(&base, c)).collect();
    let model = |c: &Case<T>| &models[cases.iter().position(|d| std::ptr::eq(c, d)).expect("own case")];
    let geo = |name, body: &str, nout| (name, format!("{PARAMS}\n    {body}"), nout);
    // Scale of a coordinate result: the point plus twice the image values (mirror p + p − c).
    let scale = |c: &Case<T>, a: usize| {
        c.args[16 + a].abs() + T::c(2.0) * c.args[..4].iter().fold(T::zero(), |s, v| s.max(v.abs()))
    };
    let twins = [
        geo("image_exists", "put(i, 0u, select(real(0.0), real(1.0), image_exists(prm, c)));", 1),
        geo("image_pos", "put2(i, 0u, image_pos(prm, c, x));", 2),
        geo("image_map", "put2(i, 0u, image_apply(image_map(prm, c), x));", 2),
        geo("inverse_pos", "put2(i, 0u, inverse_pos(prm, c, x));", 2),
        geo("image_vec", "put2(i, 0u, image_vec(prm, c, a2(i, 18u)));", 2),
        geo(
            "image_sym",
            "let s = image_sym(prm, c, Sym2(a(i, 20u), a(i, 21u))); put(i, 0u, s.xx); put(i, 1u, s.xy);",
            2,
        ),
        geo("wall_distance", "for (var w = 0u; w < 4u; w++) { put(i, w, wall_distance(prm, w, x)); }", 4),
        geo("wall_normal", "for (var w = 0u; w < 4u; w++) { put2(i, 2u * w, wall_normal(prm, w)); }", 8),
        geo("nearest_wall", "put(i, 0u, real(nearest_wall(prm, x)));", 1),
        geo("lennard_jones", "put2(i, 0u, lennard_jones(prm, x));", 2),
        geo(
            "boundary_axis",
            "var px = x.x; var py = x.y; var vx = a(i, 18u); var vy = a(i, 19u);
    boundary_axis(prm, 0u, prm.lo_x, a(i, 22u), &px, &vx);
    boundary_axis(prm, 2u, prm.lo_y, a(i, 23u), &py, &vy);
    put(i, 0u, px); put(i, 1u, py); put(i, 2u, vx); put(i, 3u, vy);",
            4,
        ),
    ];
    for (name, body, nout) in &twins {
        let twin = Twin { name, module: "geometry", body, nout: *nout };
        check(ctx, twin, &cases, tol, |c| {
            let md = model(c);
            let (code, x) = (c.ints[4], v2(c, 16));
            match *name {
                "image_exists" => vec![m(T::c(md.images.exists(code) as u8 as f64))],
                "image_pos" | "image_map" | "inverse_pos" => {
                    let r = if *name != "inverse_pos" {
                        md.images.image_pos(code, x)
                    } else {
                        md.images.inverse_pos(code, x)
                    };
                    vec![(r.x, scale(c, 0)), (r.y, scale(c, 1))]
                }
                "image_vec" => {
                    let r = md.images.image_vec(code, v2(c, 18));
                    vec![m(r.x), m(r.y)]
                }
                "image_sym" => {
                    let s = md.images.image_sym(code, Sym2 { xx: c.args[20], xy: c.args[21] });
                    vec![m(s.xx), m(s.xy)]
                }
                "wall_distance" => (0..4)
                    .map(|w| {
                        let wl = wall_of(c, w);
                        let along = if wl.axis == 0 { x.x } else { x.y };
                        (wl.wall_distance(x), along.abs() + wl.coord.abs())
                    })
                    .collect(),
                "wall_normal" => (0..4)
                    .flat_map(|w| {
                        let n = wall_of(c, w).wall_normal();
                        [m(n.x), m(n.y)]
                    })
                    .collect(),
                "nearest_wall" => {
                    let w = md.nearest_wall(x).map_or(u32::MAX as f64, |w| {
                        md.walls.iter().position(|v| std::ptr::eq(v, w)).expect("own wall") as f64
                    });
                    vec![m(T::c(w))]
                }
                "lennard_jones" => {
                    let a = lennard_jones(md, x);
                    let mag = lj_magnitude(md, x);
                    vec![(a.x, mag.x), (a.y, mag.y)]
                }
                "boundary_axis" => {
                    let (mut p, mut v) = (x, v2(c, 18));
                    boundary_axis(&md.images.x, md.lo.x, md.hi.x, &mut p.x, &mut v.x);
                    boundary_axis(&md.images.y, md.lo.y, md.hi.y, &mut p.y, &mut v.y);
                    vec![(p.x, scale(c, 0)), (p.y, scale(c, 1)), m(v.x), m(v.y)]
                }
                _ => unreachable!("every twin has a CPU side"),
            }
        });
    }
    // Every branch was taken by some case (a twin test that skips a branch cannot fail on it).
    let lj_active = models.iter().zip(&cases).filter(|(md, c)| lennard_jones(*md, v2(c, 16)) != V2::zero()).count();
    let lj_cut = cases.iter().filter(|c| c.ints[5] > 0 && lennard_jones(model(c), v2(c, 16)) == V2::zero()).count();
    let crossed = |kind: u32| {
        cases
            .iter()
            .zip(&models)
            .filter(|(c, md)| {
                (0..4).any(|s| {
                    let (a, high) = (s / 2, s % 2 == 1);
                    let (lo, hi) = if a == 0 { (md.lo.x, md.hi.x) } else { (md.lo.y, md.hi.y) };
                    let xa = c.args[16 + a];
                    c.ints[s] == kind && if high { xa > hi } else { xa < lo }
                })
            })
            .count()
    };
    let no_wall = cases.iter().filter(|c| c.ints[5] == 0).count();
    println!("geometry cases: LJ active {lj_active}, LJ beyond cut-off {lj_cut}, mirror crossed {}, periodic crossed {}, no wall {no_wall}", crossed(1), crossed(2));
    assert!(lj_active > 50 && lj_cut > 50 && crossed(1) > 50 && crossed(2) > 50 && no_wall > 50, "branch coverage");
}

/// Per-component magnitude of `lennard_jones`: Σ over the boundary points it sums of
/// |r_ib| D ((r0/r)^12 + (r0/r)^4)/r² (the two powers cancel near r0, the points may cancel).
fn lj_magnitude<T: Real>(md: &Model<T>, x: V2<T>) -> V2<T> {
    let r0 = 0.5 * md.dx.f64();
    let (mut sx, mut sy) = (0.0, 0.0);
    for w in &md.walls {
        if w.wall_distance(x).f64() >= r0 {
            continue;
        }
        let (t, t0) = if w.axis == 0 { (x.y, md.lo.y) } else { (x.x, md.lo.x) };
        let k0 = ((t - t0).f64() / r0).round();
        for dk in [-1.0, 0.0, 1.0] {
            let tb = t0.f64() + (k0 + dk) * r0;
            let b = if w.axis == 0 { [w.coord.f64(), tb] } else { [tb, w.coord.f64()] };
            let r = [x.x.f64() - b[0], x.y.f64() - b[1]];
            let r2 = r[0] * r[0] + r[1] * r[1];
            if r2 > 0.0 && r2 < r0 * r0 * 1.01 {
                let q2 = r0 * r0 / r2;
                let s = md.lj_strength.f64() * (q2.powi(6) + q2.powi(2)) / r2;
                (sx, sy) = (sx + r[0].abs() * s, sy + r[1].abs() * s);
            }
        }
    }
    V2::new(T::c(sx), T::c(sy))
}
