// contact_angle.wgsl (one workgroup): Mode A's unbalanced Young force (docs/PHYSICS.md §8.2.5) at
// each contact point `contact_line` found in the same pass. Twin of
// `cpu::contact_angle::measured_contact_cos` and of the kernel-spread weights of
// `cpu::line_force::line_force_weights`. Per point: in each of the first ANGLE_ROWS rows above
// the wall, within ANGLE_REACH_DX Δx of the point, the outermost liquid particle on the point's
// side and the nearest gas particle beyond it (reduced over the workgroup); the least-squares
// quadratic through the rows' interface positions gives cos θ_d (word 3; where fewer than two
// rows hold liquid, the rest value `params.young.z`, at which the force is zero), and
// F = σ_GS − σ_LS − σ_LG cos θ_d times s over Σ_i W(|x_i − x_cp|) is the point's line force per
// unit weight (word 4), which `young_line_acc` (common/bindings.wgsl) spreads. Dispatched only
// for a scene with the option (`Domain::ContactAngles`, core/src/gpu/stages.rs). The particles
// it reads are those of the point's window: the cells of the box holding the window and the
// kernel support around the point, one contiguous span of the evaluation's cell sort per row of
// cells (`window_of`), so a point costs its window, not N; under the direct search (no cell
// sort) the one span is every fluid particle.

#import common/neighbours

const ANGLE_THREADS: u32 = 256u;
// Beyond any u a window holds (|u| ≤ ANGLE_REACH_DX Δx): "no particle in this row".
const NONE_U: f32 = 1e30;

// Rows 0..ANGLE_ROWS reduced by max (liquid) or min (gas), then the weight sum.
var<workgroup> red: array<real, 1792>; // (ANGLE_ROWS + 1) × ANGLE_THREADS
var<workgroup> wg_count: u32;

struct RowU {
    row: i32,
    u: real,
}

// Row and u = s (x − x_cp) of a particle at p in the window of point (x_cp, s), row −1 outside
// it (at or below the wall, past the reach, above the rows).
fn angle_row(p: real2, x_cp: real, s: real) -> RowU {
    let d = p.y - params.y_wall;
    let u = s * (p.x - x_cp);
    if d <= real(0.0) || abs(u) > real(ANGLE_REACH_DX) * params.dx {
        return RowU(-1, u);
    }
    let row = u32(floor(d / params.dx));
    return RowU(select(-1, i32(row), row < ANGLE_ROWS), u);
}

// Tree reduction of `red`'s lanes: the rows by max (min when `low`), the weight sum by sum.
fn reduce_rows(t: u32, low: bool) {
    for (var stride = ANGLE_THREADS / 2u; stride > 0u; stride /= 2u) {
        workgroupBarrier();
        if t < stride {
            for (var r = 0u; r < ANGLE_ROWS; r++) {
                let a = red[r * ANGLE_THREADS + t];
                let b = red[r * ANGLE_THREADS + t + stride];
                red[r * ANGLE_THREADS + t] = select(max(a, b), min(a, b), low);
            }
            let w = ANGLE_ROWS * ANGLE_THREADS;
            red[w + t] += red[w + t + stride];
        }
    }
    workgroupBarrier();
}

// du/dt at t = 0 of the least-squares quadratic through the first n of (t_k, u_k) (a line
// through two); twin of `cpu::contact_angle::interface_slope` (n ≥ 2).
fn interface_slope(tk: array<real, ANGLE_ROWS>, uk: array<real, ANGLE_ROWS>, n: u32) -> real {
    if n == 2u {
        return (uk[1] - uk[0]) / (tk[1] - tk[0]);
    }
    // Normal equations of u = a + b t + c t² (s[e] = Σ t^e, r[e] = Σ t^e u), b by Cramer's rule.
    var s = array<real, 5>(real(0.0), real(0.0), real(0.0), real(0.0), real(0.0));
    var r = array<real, 3>(real(0.0), real(0.0), real(0.0));
    for (var k = 0u; k < n; k++) {
        var p = real(1.0);
        for (var e = 0u; e < 5u; e++) {
            if e < 3u {
                r[e] += p * uk[k];
            }
            s[e] += p;
            p *= tk[k];
        }
    }
    let a = det3(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
    let b = det3(s[0], r[0], s[2], s[1], r[1], s[3], s[2], r[2], s[4]);
    return b / a;
}

// Determinant of the rows (a, b, c), (d, e, f), (g, h, i).
fn det3(a: real, b: real, c: real, d: real, e: real, f: real, g: real, h: real, i: real) -> real {
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
}

// The fluid slots that hold every particle of a point's window (module comment): rows
// `y0..=y1` of cells `x0..=x1`, or (direct search) one row, slots 0..n_fluid.
struct Window {
    x0: i32,
    x1: i32,
    y0: i32,
    y1: i32,
    phys: bool,
}

fn window_of(cp: real2) -> Window {
#ifdef DIRECT
    return Window(0, 0, 0, 0, false);
#else
    // Below the wall only the weights' support; above it the rows or the support.
    let half = max(real(ANGLE_REACH_DX) * params.dx, params.support);
    let top = max(real(ANGLE_ROWS) * params.dx, params.support);
    let lo = grid_coords(real2(cp.x - half, cp.y - params.support));
    let hi = grid_coords(real2(cp.x + half, cp.y + top));
    return Window(lo.x, hi.x, lo.y, hi.y, physical_order());
#endif
}

// Slots [x, y) of the window's row r (cells adjacent in the sort: one span).
fn window_span(w: Window, r: i32) -> vec2<u32> {
#ifdef DIRECT
    return vec2<u32>(0u, params.n_fluid);
#else
    let row = u32(i32(params.grid_nx) * r);
    return vec2<u32>(cell_start[row + u32(w.x0)], cell_start[row + u32(w.x1) + 1u]);
#endif
}

// The particle in slot s of the window's sort.
fn window_particle(w: Window, s: u32) -> u32 {
#ifdef DIRECT
    return s;
#else
    return slot_at(s, w.phys);
#endif
}

@compute @workgroup_size(ANGLE_THREADS)
fn contact_angle(@builtin(local_invocation_index) t: u32) {
    if t == 0u {
        wg_count = min(atomicLoad(&ctl[CTL_CONTACTS_FOUND]), MAX_CONTACTS);
    }
    let count = workgroupUniformLoad(&wg_count);
    let kp = params_kernel(params);
    let none = real(NONE_U);
    let w_lane = ANGLE_ROWS * ANGLE_THREADS;
    for (var k = 0u; k < count; k++) {
        let base = CONTACT_WORDS * k;
        let cp = real2(contacts[base], contacts[base + 1u]);
        let s = contacts[base + 2u];
        // The outermost liquid particle of each row, and the weight sum.
        let win = window_of(cp);
        var liq = array<real, ANGLE_ROWS>(-none, -none, -none, -none, -none, -none);
        var wsum = real(0.0);
        for (var y = win.y0; y <= win.y1; y++) {
            let span = window_span(win, y);
            for (var slot = span.x + t; slot < span.y; slot += ANGLE_THREADS) {
                let i = window_particle(win, slot);
                let d = pos[i] - cp;
                wsum += kernel_w(kp, sqrt(d.x * d.x + d.y * d.y));
                let ru = angle_row(pos[i], cp.x, s);
                if phase[i] == 0u && ru.row >= 0 {
                    liq[ru.row] = max(liq[ru.row], ru.u);
                }
            }
        }
        for (var r = 0u; r < ANGLE_ROWS; r++) {
            red[r * ANGLE_THREADS + t] = liq[r];
        }
        red[w_lane + t] = wsum;
        reduce_rows(t, false);
        for (var r = 0u; r < ANGLE_ROWS; r++) {
            liq[r] = red[r * ANGLE_THREADS];
        }
        let wtotal = red[w_lane];
        workgroupBarrier();
        // The nearest gas particle beyond the liquid of each row.
        var gas = array<real, ANGLE_ROWS>(none, none, none, none, none, none);
        for (var y = win.y0; y <= win.y1; y++) {
            let span = window_span(win, y);
            for (var slot = span.x + t; slot < span.y; slot += ANGLE_THREADS) {
                let i = window_particle(win, slot);
                let ru = angle_row(pos[i], cp.x, s);
                if phase[i] == 1u && ru.row >= 0 && liq[ru.row] > -none && ru.u > liq[ru.row] {
                    gas[ru.row] = min(gas[ru.row], ru.u);
                }
            }
        }
        for (var r = 0u; r < ANGLE_ROWS; r++) {
            red[r * ANGLE_THREADS + t] = gas[r];
        }
        red[w_lane + t] = real(0.0);
        reduce_rows(t, true);
        if t == 0u {
            var tk = array<real, ANGLE_ROWS>(real(0.0), real(0.0), real(0.0), real(0.0), real(0.0), real(0.0));
            var uk = tk;
            var n = 0u;
            for (var r = 0u; r < ANGLE_ROWS; r++) {
                if !(liq[r] > -none) {
                    break;
                }
                let g = red[r * ANGLE_THREADS];
                tk[n] = real(f32(r)) + real(0.5);
                uk[n] = select(real(0.5) * (liq[r] + g), liq[r] + real(0.5) * params.dx, !(g < none));
                n++;
            }
            var cos_d = params.young.z;
            if n >= 2u {
                let b = interface_slope(tk, uk, n) / params.dx;
                cos_d = -b / sqrt(real(1.0) + b * b);
            }
            let force = params.young.x - params.young.y * cos_d;
            contacts[base + 3u] = cos_d;
            contacts[base + 4u] = select(real(0.0), force * s / wtotal, wtotal > real(0.0));
        }
        workgroupBarrier();
    }
}
