// normal_correction.wgsl (thread mapping): Algorithm 1, one thread per particle: near the wall
// (fluid with y − y_w ≤ band, or any coloured wall particle) the gradient towards the other
// fluid keeps its magnitude and takes the direction ±n̂_θ of the nearest contact point. In place
// on grad slot 0; nothing changes without contact points. Twin of
// `cpu::stages::normal_correction`.

#import common/bindings
#import contact

@compute @workgroup_size(64)
fn normal_correction(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let k = colour[i];
    let g = grad0[i];
    if !(k == 0 || k == 1) || g.x * g.x + g.y * g.y == real(0.0) {
        return;
    }
    if i < params.n_fluid && pos[i].y - params.y_wall > params.band {
        return;
    }
    let cp = nearest_contact(pos[i]);
    if cp < 0 {
        return;
    }
    grad0[i] = corrected_normal(g, contact_normal_of(cp), k == 0);
}
