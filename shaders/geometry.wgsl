// geometry.wgsl: the boundary geometry of a scene as pure functions of `Params` (the value of
// the `params` uniform, passed first like Rust's `&self`): image transforms of the mirror and
// periodic sides (twin of `model::Images`), wall-line distance and nearest wall (twin of
// `model::WallLine`, `Model::nearest_wall`), the Lennard-Jones wall repulsion (twin of
// `cpu::stages::lennard_jones`) and the mirror/periodic boundary fix (twin of
// `cpu::boundary_axis`). Same names on both sides. Library module: no bindings, no entry points.

#import types
#import stress
#import wall

// Map of one side of kind `kind` and value v as (sign, shift), c ↦ sign·c + shift: a mirror
// plane at v, (−1, 2v); a periodic shift by v, (1, v). The one statement of the image rules;
// −c + 2v is v + v − c and c + v is itself, exactly.
fn side_map(kind: u32, v: real) -> real2 {
    if kind == IMAGE_MIRROR {
        return real2(real(-1.0), v + v);
    }
    return real2(real(1.0), v);
}

// True when image code c = ax + 3·ay names an existing transform.
fn image_exists(prm: Params, c: u32) -> bool {
    return image_exists_of_sides(prm.image_kind, c);
}

// The same from the sides' kinds alone (`Params.image_kind`; see `image_map_of_sides`).
fn image_exists_of_sides(kind: vec4<u32>, c: u32) -> bool {
    let ax = c % 3u;
    let ay = c / 3u;
    return (ax == 0u || kind[ax - 1u] != IMAGE_NONE) && (ay == 0u || kind[1u + ay] != IMAGE_NONE);
}

// Code c's transform as a map per axis, x ↦ sign·x + shift (an axis c leaves alone: 1, 0), so a
// loop applies one code to many candidates with a multiply-add per axis.
struct ImageMap {
    sign: real2,
    shift: real2,
}

// The map of code c from the sides' kinds and values (`Params.image_kind`, `.image_value`): a
// loop over entries whose code changes from one to the next passes these two vectors rather
// than the whole `Params` by value (why: reports/engine/README.md, "Image transforms built once
// per code").
fn image_map_of_sides(kind: vec4<u32>, value: vec4<real>, c: u32) -> ImageMap {
    let ax = c % 3u;
    let ay = c / 3u;
    var m = ImageMap(real2(real(1.0), real(1.0)), real2(real(0.0), real(0.0)));
    if ax != 0u {
        let s = side_map(kind[ax - 1u], value[ax - 1u]);
        m.sign.x = s.x;
        m.shift.x = s.y;
    }
    if ay != 0u {
        let s = side_map(kind[1u + ay], value[1u + ay]);
        m.sign.y = s.x;
        m.shift.y = s.y;
    }
    return m;
}

fn image_map(prm: Params, c: u32) -> ImageMap {
    return image_map_of_sides(prm.image_kind, prm.image_value, c);
}

fn image_apply(m: ImageMap, x: real2) -> real2 {
    return x * m.sign + m.shift;
}

// The inverse of `image_apply`: (x − shift)·sign (a mirror is its own inverse: (x − 2v)·(−1) is
// 2v − x exactly; a shift by v is undone by x − v).
fn image_unapply(m: ImageMap, x: real2) -> real2 {
    return (x - m.shift) * m.sign;
}

// Position of the image of x under code c.
fn image_pos(prm: Params, c: u32, x: real2) -> real2 {
    return image_apply(image_map(prm, c), x);
}

// Inverse transform of code c.
fn inverse_pos(prm: Params, c: u32, x: real2) -> real2 {
    return image_unapply(image_map(prm, c), x);
}

// Component signs of code c (−1 per mirrored axis).
fn image_signs(prm: Params, c: u32) -> real2 {
    return image_map(prm, c).sign;
}

// Image of a vector (velocity, colour gradient).
fn image_vec(prm: Params, c: u32, v: real2) -> real2 {
    return v * image_signs(prm, c);
}

// Image of a symmetric traceless tensor (Π_xy flips once per mirrored axis).
fn image_sym(prm: Params, c: u32, t: Sym2) -> Sym2 {
    return sym_by_signs(image_signs(prm, c), t);
}

// A symmetric traceless tensor under the component signs s of an image (`image_signs`, or an
// `ImageMap`'s `sign`).
fn sym_by_signs(s: real2, t: Sym2) -> Sym2 {
    return Sym2(t.xx, t.xy * s.x * s.y);
}

// Signed distance of x in front of wall line w (positive on the fluid side).
fn wall_distance(prm: Params, w: u32, x: real2) -> real {
    var c = x.y;
    if prm.wall_axis[w] == 0u {
        c = x.x;
    }
    return (c - prm.wall_coord[w]) * prm.wall_sign[w];
}

// Unit normal of wall line w pointing into the fluid.
fn wall_normal(prm: Params, w: u32) -> real2 {
    if prm.wall_axis[w] == 0u {
        return real2(prm.wall_sign[w], real(0.0));
    }
    return real2(real(0.0), prm.wall_sign[w]);
}

// Index of the nearest wall line (first on ties), or 0xFFFFFFFF without walls.
fn nearest_wall(prm: Params, x: real2) -> u32 {
    var best = 0xFFFFFFFFu;
    var bd = real(0.0);
    for (var w = 0u; w < prm.n_walls; w++) {
        let d = wall_distance(prm, w, x);
        if best == 0xFFFFFFFFu || d < bd {
            best = w;
            bd = d;
        }
    }
    return best;
}

// Lennard-Jones repulsion of the boundary points (spacing r0 = Δx/2 on each wall line).
fn lennard_jones(prm: Params, x: real2) -> real2 {
    let r0 = real(0.5) * prm.dx;
    var a = real2(real(0.0), real(0.0));
    for (var w = 0u; w < prm.n_walls; w++) {
        if wall_distance(prm, w, x) >= r0 {
            continue;
        }
        let along_y = prm.wall_axis[w] == 0u;
        let t = select(x.x, x.y, along_y);
        let t0 = select(prm.lo_x, prm.lo_y, along_y);
        let k0 = round((t - t0) / r0);
        for (var dk = -1; dk <= 1; dk++) {
            let tb = t0 + (k0 + real(dk)) * r0;
            var b = real2(tb, prm.wall_coord[w]);
            if along_y {
                b = real2(prm.wall_coord[w], tb);
            }
            a += lj_wall_acc(x - b, r0, prm.lj_strength);
        }
    }
    return a;
}

// Reflects (mirror) or wraps (periodic) one coordinate; `lo_side` is 0 (x) or 2 (y).
fn boundary_axis(prm: Params, lo_side: u32, lo: real, hi: real, x: ptr<function, real>, v: ptr<function, real>) {
    let k0 = prm.image_kind[lo_side];
    let p0 = prm.image_value[lo_side];
    if k0 == IMAGE_MIRROR && *x < p0 {
        *x = p0 + p0 - *x;
        *v = -*v;
    } else if k0 == IMAGE_SHIFT && *x < lo {
        *x -= p0;
    }
    let k1 = prm.image_kind[lo_side + 1u];
    let p1 = prm.image_value[lo_side + 1u];
    if k1 == IMAGE_MIRROR && *x > p1 {
        *x = p1 + p1 - *x;
        *v = -*v;
    } else if k1 == IMAGE_SHIFT && *x >= hi {
        *x -= p1;
    }
}
