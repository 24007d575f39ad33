//! The neighbour-walk probe: what one thread's walk over the 3×3 cells around its particle
//! costs on an adapter, with no solver around it, so that a pass of the engine can be read
//! against the walk it contains.
//!
//! A square lattice of `side²` particles (spacing 1) sorted into cells of [`CELL_DX`] (the cell
//! size equals the support, so the 3×3 cells hold ≈ 9·[`CELL_DX`]² candidates of which
//! ≈ π·[`CELL_DX`]² are neighbours, about what the solver's cells hold). One thread per slot
//! walks the three rows of its 3×3 block as contiguous slot ranges and writes what it found. The
//! forms ([`FORMS`]) differ in one thing each:
//! * `ranges`: the candidate's position is `pos[s]` (particles stored in cell order);
//! * `indirect`: the particles are stored in a random order and slot s names its particle,
//!   `pos_perm[order[s]]` (the engine's `sorted[]` before physical ordering);
//! * `params-by-value`: as `ranges`, with every candidate's position passed through
//!   `image_pos(params, code, x)` of `shaders/geometry.wgsl`, which takes the whole `Params`
//!   uniform by value, a call per candidate (the engine's walks build each code's image map
//!   once instead; the code, 0 = the identity, comes from a uniform, so the call is not folded
//!   away and only the call differs);
//! * `pair-sum`: as `ranges`, with a Wendland weight (a square root and a few products) summed
//!   per neighbour, the least pair work a pass does;
//! * `quintic`: as `pair-sum`, with the engine's own kernel value instead (`kernel_w` of
//!   `shaders/kernel.wgsl`, the quintic spline at h = [`CELL_DX`]/3, its parameters read once
//!   per thread), the number-density pass's pair work without its epilogue.
//!
//! Each form is compiled twice, its inputs bound `read` and `read_write` (every engine binding is
//! `read_write`). Each (form, access) is timed as one dispatch per pass with beginning/end
//! timestamps, one warm-up and [`WALK_REPEATS`] timed passes, the best kept; only with
//! `TIMESTAMP_QUERY`. Every form's output is read back and checked against the host's count (or
//! sum) before its time is reported: a walk that missed candidates is an error, not a time.

use super::solver::spread;
use super::{GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use serde::Serialize;
use wgpu::util::DeviceExt;

/// Cell size and support in lattice spacings.
pub const CELL_DX: f32 = 3.6;
/// Timed passes per (form, access); the best counts.
pub const WALK_REPEATS: u32 = 5;
/// The forms, with the mode number the WGSL takes.
pub const FORMS: [(&str, u32); 5] =
    [("ranges", 0), ("indirect", 1), ("params-by-value", 2), ("pair-sum", 3), ("quintic", 4)];
/// Threads per workgroup.
const GROUP: u32 = 64;

const WALK_WGSL: &str = "
#import geometry
#import kernel

struct Probe { n: u32, grid_nx: u32, grid_ny: u32, code: u32, inv_cell: f32, support2: f32, pad1: f32, pad2: f32 }
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> probe: Probe;
#ifdef RW
@group(0) @binding(2) var<storage, read_write> pos: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read_write> pos_perm: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read_write> order: array<u32>;
@group(0) @binding(5) var<storage, read_write> cell_start: array<u32>;
#else
@group(0) @binding(2) var<storage, read> pos: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read> pos_perm: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read> order: array<u32>;
@group(0) @binding(5) var<storage, read> cell_start: array<u32>;
#endif
@group(0) @binding(6) var<storage, read_write> found_by: array<f32>;

fn position_at(s: u32, mode: u32) -> vec2<f32> {
    if mode == 1u {
        return pos_perm[order[s]];
    }
    return pos[s];
}

fn walk(slot: u32, mode: u32) -> f32 {
    let xi = position_at(slot, mode);
    let cx = i32(floor(xi.x * probe.inv_cell));
    let cy = i32(floor(xi.y * probe.inv_cell));
    var found = 0.0;
    var kp: KernelParams;
    if mode == 4u {
        kp = params_kernel(params);
    }
    for (var dy = -1; dy <= 1; dy++) {
        let y = cy + dy;
        if y < 0 || y >= i32(probe.grid_ny) {
            continue;
        }
        let x0 = max(cx - 1, 0);
        let x1 = min(cx + 1, i32(probe.grid_nx) - 1);
        let row = u32(y) * probe.grid_nx;
        let end = cell_start[row + u32(x1) + 1u];
        for (var s = cell_start[row + u32(x0)]; s < end; s++) {
            var xj = position_at(s, mode);
            if mode == 2u {
                xj = image_pos(params, probe.code, xj);
            }
            let d = xi - xj;
            let r2 = dot(d, d);
            if r2 < probe.support2 {
                if mode == 3u {
                    let q = sqrt(r2 / probe.support2);
                    let a = 1.0 - q;
                    found += a * a * a * a * (1.0 + 4.0 * q);
                } else if mode == 4u {
                    found += kernel_w(kp, sqrt(r2));
                } else {
                    found += 1.0;
                }
            }
        }
    }
    return found;
}

fn slot_of(gid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return gid.x + gid.y * nwg.x * 64u;
}
";

/// The entry point of a form.
fn entry(mode: u32) -> String {
    format!("walk_{mode}")
}

/// The probe's source: [`WALK_WGSL`] and one entry point per form, `walk_<mode>`.
fn walk_source() -> String {
    let mut s = WALK_WGSL.to_string();
    for (_, mode) in FORMS {
        s += &format!(
            "@compute @workgroup_size(64)\nfn {}(@builtin(global_invocation_id) gid: vec3<u32>, \
             @builtin(num_workgroups) nwg: vec3<u32>) {{\n    let i = slot_of(gid, nwg);\n    if i < probe.n {{ \
             found_by[i] = walk(i, {mode}u); }}\n}}\n",
            entry(mode)
        );
    }
    s
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ProbeUniform {
    n: u32,
    grid_nx: u32,
    grid_ny: u32,
    /// The image code `params-by-value` passes: 0 (the identity), read at run time so the call
    /// cannot be folded away.
    code: u32,
    inv_cell: f32,
    support2: f32,
    pad1: f32,
    pad2: f32,
}

/// The lattice in cell order, its cells, and a random storage order for `indirect`.
pub struct Lattice {
    /// Particles per side.
    pub side: u32,
    /// Positions in cell order (slot s).
    pub pos: Vec<[f32; 2]>,
    /// Start slot of each cell (row-major), and the total last.
    pub cell_start: Vec<u32>,
    /// Cells per side.
    pub grid: u32,
    /// `order[s]`: where slot s's particle is stored in `pos_perm`.
    pub order: Vec<u32>,
    /// Positions in that random order.
    pub pos_perm: Vec<[f32; 2]>,
}

impl Lattice {
    /// `side²` particles at (x + ½, y + ½), counting-sorted into cells of [`CELL_DX`]; the
    /// storage order of `indirect` is a fixed-seed shuffle.
    pub fn new(side: u32) -> Lattice {
        let grid = ((side as f32 / CELL_DX).ceil() as u32).max(1);
        let cell = |p: [f32; 2]| {
            let c = |v: f32| ((v / CELL_DX).floor() as u32).min(grid - 1);
            (c(p[1]) * grid + c(p[0])) as usize
        };
        let pts: Vec<[f32; 2]> = (0..side * side).map(|k| [(k % side) as f32 + 0.5, (k / side) as f32 + 0.5]).collect();
        let mut count = vec![0u32; (grid * grid) as usize + 1];
        for &p in &pts {
            count[cell(p) + 1] += 1;
        }
        for c in 1..count.len() {
            count[c] += count[c - 1];
        }
        let cell_start = count.clone();
        let mut next = count;
        let mut pos = vec![[0.0f32; 2]; pts.len()];
        for &p in &pts {
            let c = cell(p);
            pos[next[c] as usize] = p;
            next[c] += 1;
        }
        // Fisher–Yates with a fixed 64-bit LCG: the same shuffle on every machine.
        let mut order: Vec<u32> = (0..pos.len() as u32).collect();
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for k in (1..order.len()).rev() {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            order.swap(k, ((state >> 33) % (k as u64 + 1)) as usize);
        }
        let mut pos_perm = vec![[0.0f32; 2]; pos.len()];
        for (s, &o) in order.iter().enumerate() {
            pos_perm[o as usize] = pos[s];
        }
        Lattice { side, pos, cell_start, grid, order, pos_perm }
    }

    /// What every form must find at slot s: (neighbours, Σ Wendland weight, candidates,
    /// Σ quintic W), by the same walk on the host.
    pub fn expected(&self, s: usize) -> (u32, f64, u32, f64) {
        let kp = quintic();
        let xi = self.pos[s];
        let support2 = CELL_DX * CELL_DX;
        let (cx, cy) = ((xi[0] / CELL_DX).floor() as i64, (xi[1] / CELL_DX).floor() as i64);
        let g = self.grid as i64;
        let (mut n, mut w, mut cand, mut wq) = (0u32, 0.0f64, 0u32, 0.0f64);
        for y in (cy - 1)..=(cy + 1) {
            if y < 0 || y >= g {
                continue;
            }
            let (x0, x1) = ((cx - 1).max(0), (cx + 1).min(g - 1));
            let row = (y * g) as usize;
            for t in self.cell_start[row + x0 as usize]..self.cell_start[row + x1 as usize + 1] {
                let xj = self.pos[t as usize];
                let (dx, dy) = (xi[0] - xj[0], xi[1] - xj[1]);
                let r2 = dx * dx + dy * dy;
                cand += 1;
                if r2 < support2 {
                    n += 1;
                    let q = (r2 / support2).sqrt() as f64;
                    w += (1.0 - q).powi(4) * (1.0 + 4.0 * q);
                    wq += crate::physics::kernel::kernel_w(&kp, (r2 as f64).sqrt());
                }
            }
        }
        (n, w, cand, wq)
    }
}

/// The `quintic` form's kernel: the quintic spline whose support is the cell, h = [`CELL_DX`]/3.
fn quintic() -> crate::physics::kernel::KernelParams<f64> {
    use crate::physics::kernel::{KernelKind, KernelParams};
    KernelParams::new(KernelKind::Quintic, CELL_DX as f64 / KernelKind::Quintic.support_factor())
}

/// One (form, access) timed at one size.
#[derive(Clone, Debug, Serialize)]
pub struct WalkTime {
    /// `ranges`, `indirect`, `params-by-value`, `pair-sum`, `quintic`.
    pub form: String,
    /// `read` or `read_write` bindings.
    pub access: String,
    /// Particles.
    pub n: usize,
    /// Mean candidates per particle (host count).
    pub candidates: f64,
    /// Mean neighbours per particle (host count).
    pub neighbours: f64,
    /// Best pass (ns).
    pub best_ns: f64,
    /// Best pass per particle (ns).
    pub ns_per_particle: f64,
    /// Best pass per candidate over all particles (ps).
    pub ps_per_candidate: f64,
}

/// Times every form and access on a lattice of `side²` particles; `None` without timestamps.
/// A form whose output differs from the host's walk is an error naming the slot.
pub fn measure_walk(ctx: &GpuContext, side: u32) -> Result<Option<Vec<WalkTime>>, GpuError> {
    if !ctx.has(wgpu::Features::TIMESTAMP_QUERY) {
        return Ok(None);
    }
    let lat = Lattice::new(side);
    let n = lat.pos.len();
    let expected: Vec<(u32, f64, u32, f64)> = (0..n).map(|s| lat.expected(s)).collect();
    let candidates = expected.iter().map(|e| e.2 as f64).sum::<f64>() / n as f64;
    let neighbours = expected.iter().map(|e| e.0 as f64).sum::<f64>() / n as f64;
    let init = |label: &str, bytes: &[u8], usage| {
        ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytes, usage })
    };
    let storage = wgpu::BufferUsages::STORAGE;
    // Zero but the kernel's fields (the `quintic` form's).
    let mut p = <super::params::Params<f32> as Zeroable>::zeroed();
    let kp = quintic();
    p.kernel_kind = kp.kind.id();
    (p.h, p.inv_h, p.alpha, p.support) = (kp.h as f32, kp.inv_h as f32, kp.alpha as f32, kp.support as f32);
    let params = init("sphlab.walk.params", bytemuck::bytes_of(&p), wgpu::BufferUsages::UNIFORM);
    let grid = lat.grid;
    let uniform = ProbeUniform {
        n: n as u32,
        grid_nx: grid,
        grid_ny: grid,
        code: 0,
        inv_cell: 1.0 / CELL_DX,
        support2: CELL_DX * CELL_DX,
        pad1: 0.0,
        pad2: 0.0,
    };
    let probe = init("sphlab.walk.probe", bytemuck::bytes_of(&uniform), wgpu::BufferUsages::UNIFORM);
    let pos = init("sphlab.walk.pos", bytemuck::cast_slice(&lat.pos), storage);
    let pos_perm = init("sphlab.walk.pos_perm", bytemuck::cast_slice(&lat.pos_perm), storage);
    let order = init("sphlab.walk.order", bytemuck::cast_slice(&lat.order), storage);
    let cell_start = init("sphlab.walk.cell_start", bytemuck::cast_slice(&lat.cell_start), storage);
    let out_bytes = 4 * n as u64;
    let out = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sphlab.walk.out"),
        size: out_bytes,
        usage: storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let (gx, gy) = spread((n as u32).div_ceil(GROUP) as usize, ctx.limits.max_compute_workgroups_per_dimension);
    let mut times = Vec::new();
    for (access, defines) in [("read", &[][..]), ("read_write", &["RW"][..])] {
        let source = super::compose(&walk_source(), defines)?;
        for (form, mode) in FORMS {
            let pipeline = ctx.compute_pipeline("sphlab.walk", &source, &entry(mode))?;
            let bg = ctx.bind_group(&pipeline, &[&params, &probe, &pos, &pos_perm, &order, &cell_start, &out])?;
            let out_staging = super::staging::staging_buffer(ctx, "sphlab.walk.out_staging", out_bytes);
            // Cleared first: every particle is its own neighbour, so a slot no pass wrote reads 0
            // and fails the check.
            ctx.scoped(|d| {
                let mut enc = d.create_command_encoder(&Default::default());
                enc.clear_buffer(&out, 0, None);
                ctx.queue.submit([enc.finish()]);
            })?;
            let best = super::timing::best_pass_ns(
                ctx,
                "sphlab.walk",
                WALK_REPEATS + 1,
                |pass| {
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &bg, &[]);
                    pass.dispatch_workgroups(gx, gy, 1);
                },
                |enc| enc.copy_buffer_to_buffer(&out, 0, &out_staging, 0, out_bytes),
            )?;
            let found: Vec<f32> = super::staging::map_read(ctx, &out_staging, out_bytes)?;
            check_output(form, access, &found, &expected, mode)?;
            let Some(best_ns) = best else { return Ok(None) };
            times.push(WalkTime {
                form: form.into(),
                access: access.into(),
                n,
                candidates,
                neighbours,
                best_ns,
                ns_per_particle: best_ns / n as f64,
                ps_per_candidate: 1e3 * best_ns / (candidates * n as f64),
            });
        }
    }
    Ok(Some(times))
}

/// A form's output against the host walk ([`Lattice::expected`] per slot): counts exactly, the
/// weight sums (modes 3 and 4) to f32 rounding; the first slot off is named.
pub fn check_output(
    form: &str,
    access: &str,
    found: &[f32],
    expected: &[(u32, f64, u32, f64)],
    mode: u32,
) -> Result<(), GpuError> {
    for (s, (&f, e)) in found.iter().zip(expected).enumerate() {
        let (want, tol) = match mode {
            3 => (e.1, 1e-4 * e.1.max(1.0)),
            4 => (e.3, 1e-4 * e.3.abs()),
            _ => (e.0 as f64, 0.0),
        };
        if !f.is_finite() || (f as f64 - want).abs() > tol {
            return Err(GpuError::Mismatch(format!(
                "walk probe `{form}` ({access}): slot {s} found {f}, the host's walk {want}"
            )));
        }
    }
    Ok(())
}
