// dispatch.wgsl: the linear index of a thread or workgroup when the host spreads a dispatch
// over x and y (x, z for the block layout, whose y counts list blocks) because x alone would
// exceed the adapter's `max_compute_workgroups_per_dimension` (`GpuSolver::groups`). Every
// kernel takes its index from here, so any N up to memory is reachable; threads past the end
// return at each kernel's bounds check. Library module: no bindings, no entry points.

// Threads per workgroup of the one-thread-per-item kernels (their @workgroup_size): 64, or the
// variant's workgroup size (`.wg128`, `.wg256`; `GpuSolver::groups` sizes their grids alike).
#ifdef WG256
const GROUP_THREADS: u32 = 256u;
#else
#ifdef WG128
const GROUP_THREADS: u32 = 128u;
#else
const GROUP_THREADS: u32 = 64u;
#endif
#endif

// Linear thread index of a GROUP_THREADS-thread kernel dispatched as (gx, gy, 1).
fn linear_id(gid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return gid.x + gid.y * nwg.x * GROUP_THREADS;
}

// Linear workgroup index of a kernel dispatched as (gx, y, gz) that keeps y for itself.
fn linear_group_xz(wg: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return wg.x + wg.z * nwg.x;
}

// Linear workgroup index of a kernel dispatched as (gx, gy, 1) with its own workgroup size.
fn linear_group_xy(wg: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return wg.x + wg.y * nwg.x;
}
