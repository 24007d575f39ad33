// bindings.wgsl: the one bind group every solver stage uses (group 0; twin of `Bufs::storage`
// in src/gpu/solver_buffers.rs). All pipelines share one explicit layout, so a stage
// binds the whole particle state and touches only what it reads or writes. Also the image
// transforms of the boundary sides (twin of `model::Images`). Library module: no entry points.

#import types
#import stress

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> pos: array<real2>;
@group(0) @binding(2) var<storage, read_write> vel: array<real2>;
@group(0) @binding(3) var<storage, read_write> phase: array<u32>;
@group(0) @binding(4) var<storage, read_write> state0: array<real2>;   // r⁰ (0..n), v⁰ (n..2n)
@group(0) @binding(5) var<storage, read_write> sigma: array<real>;
@group(0) @binding(6) var<storage, read_write> chi: array<real>;
@group(0) @binding(7) var<storage, read_write> mass: array<real>;
@group(0) @binding(8) var<storage, read_write> colour: array<i32>;
@group(0) @binding(9) var<storage, read_write> rho: array<real>;
@group(0) @binding(10) var<storage, read_write> pres: array<real>;
@group(0) @binding(11) var<storage, read_write> grad: array<real2>;    // slot s of i at 2i + s
@group(0) @binding(12) var<storage, read_write> pi: array<real2>;      // (Π_xx, Π_xy)
@group(0) @binding(13) var<storage, read_write> acc: array<real2>;
@group(0) @binding(14) var<storage, read_write> vt: array<real2>;
@group(0) @binding(15) var<storage, read_write> contacts: array<real>; // (x, y, s, 0) × 32
@group(0) @binding(16) var<storage, read_write> ctl: array<atomic<u32>>;
@group(0) @binding(17) var<storage, read_write> cell_counts: array<atomic<u32>>;
@group(0) @binding(18) var<storage, read_write> cell_start: array<u32>;
@group(0) @binding(19) var<storage, read_write> sorted: array<u32>;
@group(0) @binding(20) var<storage, read_write> cell_of: array<u32>;

// Words of `ctl` (twin of `CTL_*` in src/gpu/solver_buffers.rs).
const CTL_CONTACTS_FOUND: u32 = 0u; // points found in the last contact_line (may exceed 32)
const CTL_CONTACTS: u32 = 1u;       // points kept (≤ 32), sorted by x
const CTL_BAD_STEP: u32 = 2u;       // first step with a bad particle (0xFFFFFFFF: none)
const CTL_BAD: u32 = 3u;            // 2·particle + (0 non-finite, 1 left the domain)
const CTL_VMAX: u32 = 4u;           // f32 bits of max |v| (fluids)
const CTL_AMAX: u32 = 5u;           // f32 bits of max |a| (fluids)
const CTL_CONTACTS_MAX: u32 = 6u;   // largest contact count seen since the last read

// Map of one side (0 x-low, 1 x-high, 2 y-low, 3 y-high) applied to a coordinate.
fn side_apply(side: u32, c: real) -> real {
    let v = params.image_value[side];
    if params.image_kind[side] == IMAGE_MIRROR {
        return v + v - c;
    }
    return c + v;
}

// Inverse map of one side.
fn side_inverse(side: u32, c: real) -> real {
    let v = params.image_value[side];
    if params.image_kind[side] == IMAGE_MIRROR {
        return v + v - c;
    }
    return c - v;
}

// True when image code c = ax + 3·ay names an existing transform.
fn image_exists(c: u32) -> bool {
    let ax = c % 3u;
    let ay = c / 3u;
    return (ax == 0u || params.image_kind[ax - 1u] != IMAGE_NONE)
        && (ay == 0u || params.image_kind[1u + ay] != IMAGE_NONE);
}

// Position of the image of p under code c.
fn image_pos(c: u32, p: real2) -> real2 {
    let ax = c % 3u;
    let ay = c / 3u;
    var r = p;
    if ax != 0u {
        r.x = side_apply(ax - 1u, p.x);
    }
    if ay != 0u {
        r.y = side_apply(1u + ay, p.y);
    }
    return r;
}

// Inverse transform of code c.
fn inverse_pos(c: u32, p: real2) -> real2 {
    let ax = c % 3u;
    let ay = c / 3u;
    var r = p;
    if ax != 0u {
        r.x = side_inverse(ax - 1u, p.x);
    }
    if ay != 0u {
        r.y = side_inverse(1u + ay, p.y);
    }
    return r;
}

// Component signs of code c (−1 per mirrored axis).
fn image_signs(c: u32) -> real2 {
    let ax = c % 3u;
    let ay = c / 3u;
    var s = real2(real(1.0), real(1.0));
    if ax != 0u && params.image_kind[ax - 1u] == IMAGE_MIRROR {
        s.x = real(-1.0);
    }
    if ay != 0u && params.image_kind[1u + ay] == IMAGE_MIRROR {
        s.y = real(-1.0);
    }
    return s;
}

// Image of a vector (velocity, colour gradient).
fn image_vec(c: u32, v: real2) -> real2 {
    return v * image_signs(c);
}

// Image of a symmetric traceless tensor (Π_xy flips once per mirrored axis).
fn image_sym(c: u32, t: Sym2) -> Sym2 {
    let s = image_signs(c);
    return Sym2(t.xx, t.xy * s.x * s.y);
}

// Signed distance of p in front of wall line w (positive on the fluid side).
fn wall_distance(w: u32, p: real2) -> real {
    var c = p.y;
    if params.wall_axis[w] == 0u {
        c = p.x;
    }
    return (c - params.wall_coord[w]) * params.wall_sign[w];
}

// Unit normal of wall line w pointing into the fluid.
fn wall_normal(w: u32) -> real2 {
    if params.wall_axis[w] == 0u {
        return real2(params.wall_sign[w], real(0.0));
    }
    return real2(real(0.0), params.wall_sign[w]);
}

// Index of the nearest wall line (first on ties), or 0xFFFFFFFF without walls.
fn nearest_wall(p: real2) -> u32 {
    var best = 0xFFFFFFFFu;
    var bd = real(0.0);
    for (var w = 0u; w < params.n_walls; w++) {
        let d = wall_distance(w, p);
        if best == 0xFFFFFFFFu || d < bd {
            best = w;
            bd = d;
        }
    }
    return best;
}

// Index of the contact point nearest to r (first in x order on ties), or −1 when there is none.
fn nearest_contact(r: real2) -> i32 {
    let count = atomicLoad(&ctl[CTL_CONTACTS]);
    var best = -1;
    var bd = real(0.0);
    for (var k = 0u; k < count; k++) {
        let d = r - real2(contacts[4u * k], contacts[4u * k + 1u]);
        let d2 = d.x * d.x + d.y * d.y;
        if best < 0 || d2 < bd {
            best = i32(k);
            bd = d2;
        }
    }
    return best;
}

// Outward liquid normal n̂_θ = (s·sin θ, cos θ) of contact point k (T81; sin, cos from the host).
fn contact_normal_of(k: i32) -> real2 {
    return real2(contacts[4u * u32(k) + 2u] * params.sin_theta, params.cos_theta);
}
