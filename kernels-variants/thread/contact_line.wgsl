// contact_line.wgsl (thread mapping): contact points of the liquid (phase 0) in the first-row
// band (§8.4 step 2), twin of `cpu::stages::contact_line`. `contact_line`: one thread per fluid
// particle finds its predecessor/successor among its band neighbours and appends points through
// an atomic counter (capacity MAX_CONTACTS; the largest count is kept for the overflow error).
// The points stay in the order of the appends: their one use, `nearest_contact`
// (common/bindings.wgsl), breaks distance ties by (x, s), so it picks the point the CPU's
// (x, s)-sorted list gives, and the readback sorts them (`gpu::readback`). The host clears
// ctl[CTL_CONTACTS_FOUND] first.

#import common/neighbours

fn in_band(y: real) -> bool {
    let d = y - params.y_wall;
    return d > real(0.0) && d <= params.band;
}

fn push_contact(x: real, s: real) {
    let k = atomicAdd(&ctl[CTL_CONTACTS_FOUND], 1u);
    atomicMax(&ctl[CTL_CONTACTS_MAX], k + 1u);
    if k < MAX_CONTACTS {
        contacts[4u * k] = x;
        contacts[4u * k + 1u] = params.y_wall;
        contacts[4u * k + 2u] = s;
        contacts[4u * k + 3u] = real(0.0);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn contact_line(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n_fluid || phase[i] != 0u || !in_band(pos[i].y) {
        return;
    }
    let xi = pos[i].x;
    var has_pred = false;
    var has_succ = false;
    var pred = real(0.0);
    var succ = real(0.0);
    var pred_phase = 0u;
    var succ_phase = 0u;
    var it = nb_begin(i, pos[i]);
    while nb_next(&it) {
        if it.j >= params.n_fluid || !in_band(it.xj.y) {
            continue;
        }
        let x = it.xj.x;
        if x > xi && (!has_succ || x < succ) {
            has_succ = true;
            succ = x;
            succ_phase = phase[it.j];
        }
        if x < xi && (!has_pred || x > pred) {
            has_pred = true;
            pred = x;
            pred_phase = phase[it.j];
        }
    }
    let half = real(0.5);
    if !has_succ {
        push_contact(xi + half * params.dx, real(1.0));
    } else if succ_phase != 0u {
        push_contact(half * (xi + succ), real(1.0));
    }
    if !has_pred {
        push_contact(xi - half * params.dx, real(-1.0));
    } else if pred_phase != 0u {
        push_contact(half * (xi + pred), real(-1.0));
    }
}
