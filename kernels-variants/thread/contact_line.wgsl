// contact_line.wgsl (thread mapping): contact points of the liquid (phase 0) in the first-row
// band (§8.4 step 2; no point where the liquid meets a side wall), twin of
// `cpu::stages::contact_line`. `contact_line`: one thread per fluid
// particle finds its predecessor/successor among its band neighbours and appends points through
// an atomic counter (capacity MAX_CONTACTS; the largest count is kept for the overflow error).
// The points stay in the order of the appends: `nearest_contact` (common/bindings.wgsl) breaks
// distance ties by (x, s), so it picks the point the CPU's (x, s)-sorted list gives, the other
// readers treat every point alike, and the readback sorts them (`gpu::readback`). The host
// clears ctl[CTL_CONTACTS_FOUND] first. A point's last two words (CONTACT_WORDS) start at the
// rest cos θ and a zero line force; with the unbalanced Young force the stage's second kernel,
// `contact_angle` (thread/contact_angle.wgsl), measures both.

#import common/neighbours

fn in_band(y: real) -> bool {
    let d = y - params.y_wall;
    return d > real(0.0) && d <= params.band;
}

// A side wall (a wall line across x) faces p on the side `side` (+1: +x) nearer than
// SIDE_WALL_HALF_DX half Δx: a band particle with no band neighbour there meets the wall, it is
// no free edge (twin of `cpu::stages::at_side_wall`).
fn at_side_wall(p: real2, side: real) -> bool {
    let reach = real(0.5) * real(SIDE_WALL_HALF_DX) * params.dx;
    for (var w = 0u; w < params.n_walls; w++) {
        if params.wall_axis[w] == 0u && params.wall_sign[w] * side < real(0.0)
            && wall_distance(params, w, p) < reach {
            return true;
        }
    }
    return false;
}

fn push_contact(x: real, s: real) {
    let k = atomicAdd(&ctl[CTL_CONTACTS_FOUND], 1u);
    atomicMax(&ctl[CTL_CONTACTS_MAX], k + 1u);
    if k < MAX_CONTACTS {
        contacts[CONTACT_WORDS * k] = x;
        contacts[CONTACT_WORDS * k + 1u] = params.y_wall;
        contacts[CONTACT_WORDS * k + 2u] = s;
        contacts[CONTACT_WORDS * k + 3u] = params.young.z;
        contacts[CONTACT_WORDS * k + 4u] = real(0.0);
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
    var sp = nb_spans(i, pos[i]);
    while nb_span(&sp) {
        for (var t = sp.s0; t < sp.s1; t++) {
            let nb = nb_at(sp, t);
            if !nb.hit || nb.j >= params.n_fluid || !in_band(nb.xj.y) {
                continue;
            }
            let x = nb.xj.x;
            if x > xi && (!has_succ || x < succ) {
                has_succ = true;
                succ = x;
                succ_phase = phase[nb.j];
            }
            if x < xi && (!has_pred || x > pred) {
                has_pred = true;
                pred = x;
                pred_phase = phase[nb.j];
            }
        }
    }
    let half = real(0.5);
    if !has_succ {
        if !at_side_wall(pos[i], real(1.0)) {
            push_contact(xi + half * params.dx, real(1.0));
        }
    } else if succ_phase != 0u {
        push_contact(half * (xi + succ), real(1.0));
    }
    if !has_pred {
        if !at_side_wall(pos[i], real(-1.0)) {
            push_contact(xi - half * params.dx, real(-1.0));
        }
    } else if pred_phase != 0u {
        push_contact(half * (xi + pred), real(-1.0));
    }
}
