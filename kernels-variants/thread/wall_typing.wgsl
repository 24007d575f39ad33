// wall_typing.wgsl (thread mapping): Algorithm 2, one thread per wall particle: below y_w, the
// side of the interpolation line through the nearest contact point gives the liquid (0) or gas
// (1) colour; otherwise (or without contact points) untyped. Mass per T83. Twin of
// `cpu::stages::wall_typing`.

#import common/bindings
#import contact

@compute @workgroup_size(GROUP_THREADS)
fn wall_typing(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = params.n_fluid + linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    var c = NO_COLOUR;
    let r = pos[i];
    if r.y < params.y_wall {
        let k = nearest_contact(r);
        if k >= 0 {
            let tp = real2(contacts[4u * u32(k)], contacts[4u * u32(k) + 1u]);
            c = select(1, 0, contact_side(r, tp, contact_normal_of(k)) < real(0.0));
        }
    }
    colour[i] = c;
    mass[i] = params.mass[select(params.wall_phase, u32(c), c >= 0)];
}
