//! The device-resident particle state of the GPU solver and its one bind group (twin of
//! `shaders/bindings.wgsl`: binding k here is binding k there). All stages share one explicit
//! layout (uniform at 0, read-write storage 1..=22), so a stage binds everything and touches
//! what it needs. Every allocation is checked against the adapter limits (`GpuError::TooLarge`
//! names the buffer).

use super::params::Params;
use super::{GpuContext, GpuError, GpuVec, Uniform};
use crate::model::{CONTACT_WORDS, MAX_CONTACTS};
use crate::neighbours::cells::CellBox;
use crate::real::{Real, V2};

/// Words of the control buffer (`CTL_*` in `shaders/bindings.wgsl`).
pub mod ctl {
    /// Contact points found by the last `contact_line`.
    pub const CONTACTS_FOUND: usize = 0;
    /// Contact points kept (≤ 32).
    pub const CONTACTS: usize = 1;
    /// First bad step (`u32::MAX`: none).
    pub const BAD_STEP: usize = 2;
    /// 2·particle + kind (0 non-finite, 1 left the domain).
    pub const BAD: usize = 3;
    /// f32 bits of max |v|.
    pub const VMAX: usize = 4;
    /// f32 bits of max |a|.
    pub const AMAX: usize = 5;
    /// Largest contact count seen since the last read (sticky overflow detector).
    pub const CONTACTS_MAX: usize = 6;
    /// Device clock: steps completed (`gpu::clock`).
    pub const STEP: usize = 7;
    /// First step whose evaluations overflowed a list or the fixed-point range (`u32::MAX`: none).
    pub const OVER_STEP: usize = 8;
    /// Workgroups done in a fused integrator stage (the last one ticks the clock and scans the
    /// cell counts) or in `reduce_max` (the last one sets dt); back to 0 then.
    pub const DONE: usize = 9;
    /// First step whose cell scan did not sum to the fluid count (`u32::MAX`: none): the
    /// scan read counts that were not all visible yet (`scan_total`, common/neighbours.wgsl).
    pub const SCAN_MISS: usize = 10;
    /// Words in the buffer.
    pub const LEN: usize = 12;
}

/// Number of storage bindings after the uniform (with the variant group's 9 and the reorder
/// group's 1, 32: lavapipe's per-stage maximum).
pub const N_STORAGE: u32 = 22;

/// The device's σ records of the number densities `sigma`: (σ, 1/σ²) each
/// (`physics::pair::inv_sigma2`).
pub fn sigma_pairs<T: Real>(sigma: &[T]) -> Vec<V2<T>> {
    sigma.iter().map(|&s| V2::new(s, crate::physics::pair::inv_sigma2(s))).collect()
}

/// The number densities of the device's σ records.
pub fn sigma_of<T: Real>(records: Vec<V2<T>>) -> Vec<T> {
    records.into_iter().map(|r| r.x).collect()
}

/// The cell of `p` on `grid` (clamped into it), exactly as `cell_index` in
/// common/neighbours.wgsl computes it (a subtraction, a multiplication and a floor in `T`).
pub fn cell_of_pos<T: Real>(grid: &CellBox<T>, p: V2<T>) -> u32 {
    let (nx, ny) = (grid.nx as i64, grid.ny as i64);
    let fx = ((p.x - grid.origin.x) * grid.inv_cell).f64().floor() as i64;
    let fy = ((p.y - grid.origin.y) * grid.inv_cell).f64().floor() as i64;
    (fx.clamp(0, nx - 1) + nx * fy.clamp(0, ny - 1)) as u32
}

/// The walls' static sort: walls never move, so the host sorts them once (by cell, then index)
/// into the slots n_fluid..n after the fluids' counting sort; the neighbour loops walk a row's
/// fluid slots, then its wall slots (common/neighbours.wgsl).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WallCells {
    /// Each cell's first wall slot (cells + 1, absolute: from n_fluid).
    pub start: Vec<u32>,
    /// The wall in each wall slot (`sorted[n_fluid..n]`).
    pub list: Vec<u32>,
    /// Each wall's cell (`cell_of[n_fluid..n]`).
    pub cell_of: Vec<u32>,
}

/// The walls' static sort of `pos` (fluids first, `n_fluid` of them) on `grid`.
pub fn wall_cells<T: Real>(grid: &CellBox<T>, pos: &[V2<T>], n_fluid: usize) -> WallCells {
    let cell_of: Vec<u32> = pos[n_fluid..].iter().map(|&p| cell_of_pos(grid, p)).collect();
    let mut start = vec![0u32; grid.cells() + 1];
    for &c in &cell_of {
        start[c as usize + 1] += 1;
    }
    start[0] = n_fluid as u32;
    for c in 0..grid.cells() {
        start[c + 1] += start[c];
    }
    let mut cursor = start.clone();
    let mut list = vec![0u32; cell_of.len()];
    for (w, &c) in cell_of.iter().enumerate() {
        list[(cursor[c as usize] - n_fluid as u32) as usize] = (n_fluid + w) as u32;
        cursor[c as usize] += 1;
    }
    WallCells { start, list, cell_of }
}

/// A persistent array and its twin, in their first roles.
type Twins<X> = (GpuVec<X>, GpuVec<X>);

/// The buffers (fluids first, then walls). Five arrays that persist across the neighbour search
/// come with a twin the evaluation recomputes after it — (pos, grad0), (vel, grad1), (pos0, pi),
/// (vel0, sigma), (mass, rho) — and a renumbering writes each particle into the twin at its slot
/// (search/reorder.wgsl), after which the two swap roles ([`Bufs::swap_twins`]): the solver binds
/// the group of the current roles ([`Bufs::bind_group`] of each), and the accessors name the
/// buffer that now plays each role.
pub struct Bufs<T: Real> {
    pub params: Uniform<Params<T>>,
    /// (pos, grad0), (vel, grad1), (pos0, pi), (vel0, sigma) in their first roles.
    twins: [Twins<V2<T>>; 4],
    /// (mass, rho) in their first roles.
    mass_rho: Twins<T>,
    /// The twins have swapped roles (an odd number of renumberings recorded).
    swapped: std::cell::Cell<bool>,
    pub phase: GpuVec<u32>,
    pub chi: GpuVec<T>,
    pub colour: GpuVec<i32>,
    pub p: GpuVec<T>,
    pub acc: GpuVec<V2<T>>,
    pub vt: GpuVec<V2<T>>,
    pub contacts: GpuVec<T>,
    pub ctl: GpuVec<u32>,
    pub cell_count: GpuVec<u32>,
    pub cell_start: GpuVec<u32>,
    pub sorted: GpuVec<u32>,
    pub cell_of: GpuVec<u32>,
}

/// The accessors of the twin roles: `name: element type = pair, first role?` each, with its doc.
macro_rules! twin_roles {
    ($($(#[$doc:meta])* $name:ident: $x:ty = $pair:ident $([$k:literal])?, $first:literal;)*) => {
        impl<T: Real> Bufs<T> {
            $($(#[$doc])* pub fn $name(&self) -> &GpuVec<$x> {
                Self::role(&self.$pair$([$k])?, $first, self.swapped.get())
            })*
        }
    };
}

twin_roles! {
    /// Positions.
    pos: V2<T> = twins[0], true;
    /// Velocities.
    vel: V2<T> = twins[1], true;
    /// r⁰ of the midpoint step.
    pos0: V2<T> = twins[2], true;
    /// v⁰ of the midpoint step, v_{n+½} of Verlet's.
    vel0: V2<T> = twins[3], true;
    /// Particle masses.
    mass: T = mass_rho, true;
    /// Colour-gradient slot 0 (one binding per slot: `grad_at` in bindings.wgsl).
    grad0: V2<T> = twins[0], false;
    /// Colour-gradient slot 1.
    grad1: V2<T> = twins[1], false;
    /// (Π_xx, Π_xy).
    pi: V2<T> = twins[2], false;
    /// (σ, 1/σ²) of each particle: the number-density pass writes both, so the pair sums read
    /// 1/σ_j² instead of dividing per pair ([`sigma_pairs`], [`sigma_of`]).
    sigma: V2<T> = twins[3], false;
    /// Densities.
    rho: T = mass_rho, false;
}

impl<T: Real> Bufs<T> {
    /// Allocates the state of `n` particles on a grid of `cells` cells.
    pub fn new(ctx: &GpuContext, params: &Params<T>, n: usize, cells: usize) -> Result<Self, GpuError> {
        let v2 = |name: &str, len| GpuVec::<V2<T>>::new(ctx, &format!("sphlab.{name}"), len);
        let s = |name: &str, len| GpuVec::<T>::new(ctx, &format!("sphlab.{name}"), len);
        let u = |name: &str, len| GpuVec::<u32>::new(ctx, &format!("sphlab.{name}"), len);
        Ok(Self {
            params: Uniform::new(ctx, "sphlab.params", params),
            twins: [
                (v2("pos", n)?, v2("grad0", n)?),
                (v2("vel", n)?, v2("grad1", n)?),
                (v2("pos0", n)?, v2("pi", n)?),
                (v2("vel0", n)?, v2("sigma", n)?),
            ],
            mass_rho: (s("mass", n)?, s("rho", n)?),
            swapped: std::cell::Cell::new(false),
            phase: u("phase", n)?,
            chi: s("chi", n)?,
            colour: GpuVec::new(ctx, "sphlab.colour", n)?,
            p: s("p", n)?,
            acc: v2("acc", n)?,
            vt: v2("vt", n)?,
            contacts: s("contacts", CONTACT_WORDS * MAX_CONTACTS)?,
            ctl: u("ctl", ctl::LEN)?,
            // The counts, then the block sums of the parallel scan (search/cell_scan.wgsl).
            cell_count: u("cell_count", cells + crate::gpu::plan::scan_blocks(cells))?,
            // This search's fluid starts and lists, then the previous search's (kept by the
            // cell scan and the count for the merge of common/cell_lists.wgsl); the walls'
            // static starts after the starts, their list in the slots n_fluid..n ([`WallCells`]).
            cell_start: u("cell_start", 3 * (cells + 1))?,
            sorted: u("sorted", 2 * n)?,
            cell_of: u("cell_of", n)?,
        })
    }

    /// The buffer playing the first (`first`) or second role of a twin pair, with the roles
    /// swapped when `swapped`.
    fn role<X>(pair: &(X, X), first: bool, swapped: bool) -> &X {
        if first != swapped {
            &pair.0
        } else {
            &pair.1
        }
    }

    /// Swaps the roles of every twin pair (after a renumbering wrote the particles into the
    /// second ones); the bind group of the new roles is [`Self::roles_swapped`]'s.
    pub fn swap_twins(&self) {
        self.swapped.set(!self.swapped.get());
    }

    /// True while the twins play swapped roles (index of the solver's bind group).
    pub fn roles_swapped(&self) -> bool {
        self.swapped.get()
    }

    /// Writes the walls' static sort (`cells` cells, `n_fluid` fluids first).
    pub fn upload_walls(&self, ctx: &GpuContext, w: &WallCells, cells: usize, n_fluid: usize) {
        let put = |v: &GpuVec<u32>, at: usize, data: &[u32]| {
            if !data.is_empty() {
                ctx.queue.write_buffer(&v.buffer, 4 * at as u64, bytemuck::cast_slice(data));
                ctx.traffic.write();
            }
        };
        put(&self.cell_start, 2 * (cells + 1), &w.start);
        put(&self.sorted, n_fluid, &w.list);
        put(&self.cell_of, n_fluid, &w.cell_of);
    }

    /// The storage buffers in binding order 1..=22, the twins in their roles when `swapped`.
    pub(crate) fn storage_with(&self, swapped: bool) -> [&wgpu::Buffer; N_STORAGE as usize] {
        let (t, m) = (&self.twins, &self.mass_rho);
        let at = |k: usize, first: bool| &Self::role(&t[k], first, swapped).buffer;
        [
            at(0, true),
            at(1, true),
            &self.phase.buffer,
            at(2, true),
            at(3, true),
            at(3, false),
            &self.chi.buffer,
            &Self::role(m, true, swapped).buffer,
            &self.colour.buffer,
            &Self::role(m, false, swapped).buffer,
            &self.p.buffer,
            at(0, false),
            at(1, false),
            at(2, false),
            &self.acc.buffer,
            &self.vt.buffer,
            &self.contacts.buffer,
            &self.ctl.buffer,
            &self.cell_count.buffer,
            &self.cell_start.buffer,
            &self.sorted.buffer,
            &self.cell_of.buffer,
        ]
    }

    /// The storage buffers in binding order 1..=22, the twins in their current roles.
    pub(crate) fn storage(&self) -> [&wgpu::Buffer; N_STORAGE as usize] {
        self.storage_with(self.swapped.get())
    }

    /// The bind group of `layout` over these buffers, the twins in their current roles.
    pub fn bind_group(&self, ctx: &GpuContext, layout: &wgpu::BindGroupLayout) -> Result<wgpu::BindGroup, GpuError> {
        self.bind_group_with(ctx, layout, self.swapped.get())
    }

    /// The bind groups of `layout` with the twins in their first roles, then swapped.
    pub fn bind_groups(
        &self,
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
    ) -> Result<[wgpu::BindGroup; 2], GpuError> {
        Ok([self.bind_group_with(ctx, layout, false)?, self.bind_group_with(ctx, layout, true)?])
    }

    fn bind_group_with(
        &self,
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        swapped: bool,
    ) -> Result<wgpu::BindGroup, GpuError> {
        let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: self.params.buffer.as_entire_binding() }];
        for (k, b) in self.storage_with(swapped).into_iter().enumerate() {
            entries.push(wgpu::BindGroupEntry { binding: k as u32 + 1, resource: b.as_entire_binding() });
        }
        ctx.scoped(|d| {
            d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("sphlab.state"), layout, entries: &entries })
        })
    }
}

/// The shared bind group layout and pipeline layout.
pub fn layouts(ctx: &GpuContext) -> Result<(wgpu::BindGroupLayout, wgpu::PipelineLayout), GpuError> {
    let need = N_STORAGE;
    if ctx.limits.max_storage_buffers_per_shader_stage < need {
        return Err(GpuError::Unsupported(format!(
            "the solver binds {need} storage buffers; the adapter allows {} per shader stage",
            ctx.limits.max_storage_buffers_per_shader_stage
        )));
    }
    let mut entries = vec![wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }];
    for k in 1..=N_STORAGE {
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: k,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        });
    }
    ctx.scoped(|d| {
        let bgl = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sphlab.state"),
            entries: &entries,
        });
        let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sphlab.state"),
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });
        (bgl, pl)
    })
}
