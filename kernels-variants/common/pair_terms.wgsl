// pair_terms.wgsl: the per-pair bodies of the three pair-sum stages (number_density,
// colour_gradient, acceleration), shared by the `thread` kernels over the search iterator
// (thread/*.wgsl, through `pair_of`), the list-driven `thread` kernels (list/pair_sums.wgsl, through
// `list_pair`), the block mappings (block/*.wgsl) and their finalize kernels, so every mapping
// composes the physics of shaders/pair.wgsl in one place. Each
// `*_pair` returns the contribution of one slot; each `*_out` applies the per-particle
// prefactors (σ_i, 1/m_i, gravity, Lennard-Jones) and writes the field, exactly as the
// `thread` kernels of kernels-variants/thread/ do (twins of `cpu::stages`).
// Kernel values: `CACHED` defined = W_ij and F'(r_ij) read from the cache written by
// search/nbr_list.wgsl; otherwise recomputed on demand (the thesis's two policies, §6.5).
// With `FUSED` (a fused evaluation, core/src/gpu/stages.rs) the output functions also run the
// per-particle epilogues the stage table fuses into their pass (`FUSE_<STAGE>`,
// common/epilogues.wgsl) in the same thread, right after the output is written.
// Library module (needs common/variant_bindings); no entry points.

#import common/variant_bindings
#ifdef MASK_LISTS
#import common/mask_lists
#endif
#import pair
#import wall
#ifdef FUSED
#import common/epilogues
#ifdef FUSE_WALL_PRESSURE
#import common/wall_pressure
#endif
#endif

// One list entry of particle i: neighbour, image code, slot, image position, x_ij, r.
struct Pair {
    j: u32,
    code: u32,
    slot: u32,
    xj: real2,
    x_ij: real2,
    r2: real,
    r: real,
}

// `Pair.slot` of a neighbour found by the search iterator (no list slot: kernel values are
// always recomputed).
const NO_SLOT: u32 = 0xFFFFFFFFu;

// The pair of particle i at xi and neighbour j under image `code` at image position xj.
fn pair_of(xi: real2, j: u32, code: u32, xj: real2) -> Pair {
    var p: Pair;
    p.j = j;
    p.code = code;
    p.slot = NO_SLOT;
    p.xj = xj;
    p.x_ij = xi - xj;
    p.r2 = p.x_ij.x * p.x_ij.x + p.x_ij.y * p.x_ij.y;
    p.r = sqrt(p.r2);
    return p;
}

// Number of valid entries of i's list (an overflowing particle is reported by the host; with
// `MASK_LISTS` counts[i] is the number of entries the mask holds).
fn list_len(i: u32) -> u32 {
    return min(counts[i], NBR_SLOTS);
}

// Entry k (< list_len(i)) of the list of particle i at xi.
fn list_pair(i: u32, xi: real2, k: u32) -> Pair {
#ifdef MASK_LISTS
    let e = mask_entry(i, xi, k);
    return pair_of(xi, e.x, e.y, image_apply(image_map_of(e.y), pos[e.x]));
#else
    return pair_at(xi, nbr_slot(i, k));
#endif
}

// The entry in `slot` (= nbr_slot(i, k)) of particle i at xi.
fn pair_at(xi: real2, slot: u32) -> Pair {
    let e = nbr[slot];
    var p: Pair;
    p.j = e & PACK_MASK;
    p.code = e >> PACK_SHIFT;
    p.slot = slot;
    p.xj = image_apply(image_map_of(p.code), pos[p.j]);
    p.x_ij = xi - p.xj;
    p.r2 = p.x_ij.x * p.x_ij.x + p.x_ij.y * p.x_ij.y;
    p.r = sqrt(p.r2);
    return p;
}

// W_ij.
fn pair_w(kp: KernelParams, p: Pair) -> real {
#ifdef CACHED
    if p.slot != NO_SLOT {
        return cache_wf[p.slot].x;
    }
#endif
    return kernel_w(kp, p.r);
}

// F'(r_ij).
fn pair_dwdr(kp: KernelParams, p: Pair) -> real {
#ifdef CACHED
    if p.slot != NO_SLOT {
        return cache_wf[p.slot].y;
    }
#endif
    return kernel_dwdr(kp, p.r);
}

// number_density: (W_ij, W_ij when j is of the same kind) (T66, T46); the second sum is used
// only when Holmes χ is active (`density_out`), so the pair needs no stage flag.
fn density_pair(i: u32, kp: KernelParams, p: Pair) -> real2 {
    let w = pair_w(kp, p);
    let same = (p.j < params.n_fluid) == (i < params.n_fluid);
    return real2(w, select(real(0.0), w, same));
}

fn density_out(i: u32, s: real2) {
    // 1/σ² once per particle, next to σ (every pair term reads it from both sides).
    sigma[i] = real2(s.x, inv_sigma2(s.x));
    chi[i] = select(real(0.0), s.y / s.x, params_has(params, STAGE_HOLMES));
#ifdef FUSE_WALL_TYPING
    if i >= params.n_fluid {
        wall_typing_at(i);
    }
#endif
#ifdef FUSE_EQUATION_OF_STATE
    equation_of_state_at(i);
#endif
}

// colour_gradient: ∇_iW_ij/σ_j² in the slot of colour l = colour[j] (T71), for colour k of i.
struct Grad2 {
    g0: real2,
    g1: real2,
}

fn grad_pair(k: i32, kp: KernelParams, p: Pair) -> Grad2 {
    var g = Grad2(real2(real(0.0), real(0.0)), real2(real(0.0), real(0.0)));
    if k < 0 {
        return g;
    }
    let l = colour[p.j];
    if l < 0 || l == k || sigma_of_rows(params.sigma0, params.sigma1, params.sigma2, k, l) == real(0.0) {
        return g;
    }
    let gw = grad_w_ij(pair_dwdr(kp, p), p.x_ij, p.r);
    let t = colour_gradient_ij(sigma[p.j].y, gw);
    let first = (l < k && l == 0) || (l > k && l == 1);
    if first {
        g.g0 = t;
    } else {
        g.g1 = t;
    }
    return g;
}

fn grad_out(i: u32, g: Grad2) {
    grad0[i] = g.g0 * sigma[i].x;
    grad1[i] = g.g1 * sigma[i].x;
#ifdef FUSE_NORMAL_CORRECTION
    normal_correction_at(i);
#endif
#ifdef FUSE_SURFACE_STRESS
    surface_stress_at(i);
#endif
#ifdef FUSE_WALL_PRESSURE
    if i >= params.n_fluid {
        wall_pressure_at(i);
    }
#endif
}

// acceleration: what the pair terms need to know about particle i.
struct AccI {
    xi: real2,
    vi: real2,
    p_i: real,
    inv_s2_i: real,
    eta_i: real,
    pi_i: Sym2,
    wall: u32,
    d_i: real,
    viscous: bool, // the stage flags, read once per particle
    surface: bool,
}

fn acc_ctx(i: u32) -> AccI {
    var c: AccI;
    c.xi = pos[i];
    c.vi = vel[i];
    c.p_i = pres[i];
    c.inv_s2_i = sigma[i].y;
    c.eta_i = params.eta[phase[i]];
    c.pi_i = Sym2(pi[i].x, pi[i].y);
    c.wall = nearest_wall(params, c.xi);
    c.d_i = real(0.0);
    c.viscous = params_has(params, STAGE_VISCOSITY);
    c.surface = params_has(params, STAGE_SURFACE);
    if c.wall != 0xFFFFFFFFu {
        c.d_i = wall_distance(params, c.wall, c.xi);
    }
    return c;
}

// Pressure (T68) + viscous (T70, Morris or Holmes wall ghost velocity) + surface (T76) term of
// fluid particle i (with context c) from one pair; zero for the self pair.
fn acc_pair(i: u32, c: AccI, kp: KernelParams, p: Pair) -> real2 {
    if p.r2 == real(0.0) {
        return real2(real(0.0), real(0.0));
    }
    let j = p.j;
    let dwdr = pair_dwdr(kp, p);
    let gw = grad_w_ij(dwdr, p.x_ij, p.r);
    let inv_s2_j = sigma[j].y;
    var sum = pressure_acc_ij(c.p_i, c.inv_s2_i, pres[j], inv_s2_j, gw);
    // Component signs of j's image (v and Π_xy flip per mirrored axis).
    let sign = image_map_of(p.code).sign;
    if c.viscous {
        let fac = viscous_fac_ij(dwdr, p.r, kp.h);
        var eta_ij = c.eta_i;
        var v_ij = c.vi;
        if j < params.n_fluid {
            eta_ij = harmonic_viscosity(c.eta_i, params.eta[phase[j]]);
            v_ij = c.vi - vel[j] * sign;
        } else if c.wall != 0xFFFFFFFFu {
            var beta = real(1.0);
            if params.wall_velocity == WALL_VELOCITY_HOLMES {
                beta = holmes_beta(chi[i], chi[j], params.chi_floor, params.beta_max);
            } else {
                beta = noslip_beta(c.d_i, -wall_distance(params, c.wall, p.xj), params.beta_max, params.dx);
            }
            v_ij = wall_relative_velocity(c.vi, beta, params.wall_free_slip[c.wall] != 0u, wall_normal(params, c.wall));
        }
        if params.viscous_form == VISCOUS_FORM_PROJECTED {
            sum += viscous_projected_acc_ij(eta_ij, c.inv_s2_i, inv_s2_j, fac, v_ij, p.x_ij, p.r2);
        } else {
            sum += viscous_acc_ij(eta_ij, c.inv_s2_i, inv_s2_j, fac, v_ij);
        }
    }
    if c.surface {
        let pi_j = sym_by_signs(sign, Sym2(pi[j].x, pi[j].y));
        sum += surface_acc_ij(c.pi_i, c.inv_s2_i, pi_j, inv_s2_j, gw);
    }
    return sum;
}

// a_i = Σ/m_i + g (+ Lennard-Jones, + the unbalanced Young force); walls get zero.
fn acc_out(i: u32, sum: real2) {
    if i >= params.n_fluid {
        acc[i] = real2(real(0.0), real(0.0));
        return;
    }
    var a = sum / mass[i] + real2(params.gravity_x, params.gravity_y);
    if params_has(params, STAGE_LJ) {
        a += lennard_jones(params, pos[i]);
    }
    if params_has(params, STAGE_YOUNG_UNBALANCED) {
        a.x += young_line_acc(i);
    }
    acc[i] = a;
}
