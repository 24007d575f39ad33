// kernel_table.wgsl: tabulates W(r) and ∂W/∂r(r) for one KernelParams over an array of radii.
// A diagnostic entry point (kernel plots, smoke test of the variant composition path), not a
// solver stage. Twin: `physics::kernel::{kernel_w, kernel_dwdr}` applied element-wise.

#import kernel

@group(0) @binding(0) var<uniform> kp: KernelParams;
@group(0) @binding(1) var<storage, read> radii: array<real>;
@group(0) @binding(2) var<storage, read_write> table: array<real2>; // (W, ∂W/∂r) per radius

@compute @workgroup_size(64)
fn kernel_table(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&radii) {
        return;
    }
    let r = radii[i];
    table[i] = real2(kernel_w(kp, r), kernel_dwdr(kp, r));
}
