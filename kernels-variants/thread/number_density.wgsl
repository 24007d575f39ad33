// number_density.wgsl (thread mapping): σ_i = Σ_j W_ij over the neighbours (self and images
// included, T66) and the Holmes ratio χ_i = Σ_{same kind} W / σ_i when active. One thread per
// particle. Twin of `cpu::stages::number_density`.

#import common/neighbours

@compute @workgroup_size(64)
fn number_density(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n {
        return;
    }
    let kp = params_kernel(params);
    let holmes = params_has(params, STAGE_HOLMES);
    let fluid_i = i < params.n_fluid;
    let xi = pos[i];
    var s = real(0.0);
    var same = real(0.0);
    var it = nb_begin(i, xi);
    while nb_next(&it) {
        let d = xi - it.xj;
        let w = kernel_w(kp, sqrt(d.x * d.x + d.y * d.y));
        s += w;
        if holmes && (it.j < params.n_fluid) == fluid_i {
            same += w;
        }
    }
    sigma[i] = s;
    chi[i] = select(real(0.0), same / s, holmes);
}
