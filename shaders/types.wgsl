// types.wgsl: the `Params` uniform shared by every solver stage (twin of `src/gpu/params.rs`,
// whose test checks sizes and offsets against this file through naga). Every physical constant
// of a scene lives here, so a new scene only rewrites this buffer and never rebuilds a pipeline.
// Layout rule: a block of u32 (a multiple of 8 words, so the reals start 32-byte aligned in
// f64), then real scalars (a multiple of 4), then vec4<real> blocks; no nested structs.
// Library module: structs, consts and small accessors only (no bindings, no entry points).

#import kernel

const STAGE_HOLMES: u32 = 1u;
const STAGE_CONTACT_LINE: u32 = 2u;
const STAGE_WALL_TYPING: u32 = 4u;
const STAGE_WALL_PRESSURE: u32 = 8u;
const STAGE_SURFACE: u32 = 16u;
const STAGE_NORMAL_CORRECTION: u32 = 32u;
const STAGE_VISCOSITY: u32 = 64u;
const STAGE_LJ: u32 = 128u;
const STAGE_XSPH: u32 = 256u;
const STAGE_YOUNG_UNBALANCED: u32 = 512u;

const IMAGE_NONE: u32 = 0u;
const IMAGE_MIRROR: u32 = 1u;
const IMAGE_SHIFT: u32 = 2u;

const WALL_VELOCITY_MORRIS: u32 = 0u;
const WALL_VELOCITY_HOLMES: u32 = 1u;

const VISCOUS_FORM_LAPLACIAN: u32 = 0u;
const VISCOUS_FORM_PROJECTED: u32 = 1u;

const CONTACT_MODE_NONE: u32 = 0u;
const CONTACT_MODE_A: u32 = 1u;
const CONTACT_MODE_B: u32 = 2u;

const NO_COLOUR: i32 = -1;
const COLOUR_WALL: i32 = 2;
const MAX_CONTACTS: u32 = 32u;
// Words per contact point in `contacts`: x, y, s, cos θ_d measured there (Mode A's unbalanced
// Young force, docs/PHYSICS.md §8.2.5), and that point's line force per unit weight, F s / Σ_i W_i.
const CONTACT_WORDS: u32 = 5u;
const ANGLE_ROWS: u32 = 6u;        // rows above the wall whose interface gives θ_d (§8.2.5)
const ANGLE_REACH_DX: u32 = 12u;   // half-width of the window around the point, in Δx
const SIDE_WALL_HALF_DX: u32 = 3u; // a first-row particle this near a side wall meets it (§8.4)

struct Params {
    kernel_kind: u32,
    n: u32,
    n_fluid: u32,
    wall_phase: u32,
    contact_mode: u32,
    n_walls: u32,
    stages: u32,
    step: u32,
    wall_velocity: u32,
    grid_nx: u32,
    grid_ny: u32,
    n_phases: u32,
    viscous_form: u32,
    pad1: u32,
    pad2: u32,
    pad3: u32,
    image_kind: vec4<u32>,    // x-low, x-high, y-low, y-high: IMAGE_*
    wall_axis: vec4<u32>,     // per wall line: 0 (normal along x) or 1
    wall_free_slip: vec4<u32>,
    pad4: vec4<u32>,
    h: real,
    inv_h: real,
    alpha: real,
    support: real,
    support2: real,
    dx: real,
    sin_theta: real,
    cos_theta: real,
    band: real,
    y_wall: real,
    beta_max: real,
    chi_floor: real,
    lj_strength: real,
    xsph: real,
    gravity_x: real,
    gravity_y: real,
    lo_x: real,
    lo_y: real,
    hi_x: real,
    hi_y: real,
    dt: real,
    grid_origin_x: real,
    grid_origin_y: real,
    grid_inv_cell: real,
    image_value: vec4<real>,  // mirror plane or periodic shift, per side as image_kind
    wall_coord: vec4<real>,
    wall_sign: vec4<real>,
    rho0: vec4<real>,         // per phase (2 used)
    mass: vec4<real>,
    stiffness: vec4<real>,
    gamma: vec4<real>,
    p_b: vec4<real>,
    eta: vec4<real>,
    sigma0: vec4<real>,       // σ table rows (colour 0, 1, 2), column = other colour
    sigma1: vec4<real>,
    sigma2: vec4<real>,
    young: vec4<real>,        // the unbalanced Young force: σ_GS − σ_LS, σ_LG, cos θ at rest, unused
}

// Kernel constants in the form `shaders/kernel.wgsl` takes them.
fn params_kernel(p: Params) -> KernelParams {
    return KernelParams(p.kernel_kind, p.h, p.inv_h, p.alpha, p.support);
}

// σ^{kl} between colours k and l (0, 1 fluids; 2 wall phase S).
fn params_sigma(p: Params, k: i32, l: i32) -> real {
    return sigma_of_rows(p.sigma0, p.sigma1, p.sigma2, k, l);
}

// σ^{kl} from the table's three rows, for a pair loop that passes the rows rather than the whole
// `Params` by value (why: shaders/geometry.wgsl, `image_map_of_sides`).
fn sigma_of_rows(r0: vec4<real>, r1: vec4<real>, r2: vec4<real>, k: i32, l: i32) -> real {
    var row = r0;
    if k == 1 {
        row = r1;
    } else if k == 2 {
        row = r2;
    }
    return row[l];
}

// True when stage bit `s` (STAGE_*) is active.
fn params_has(p: Params, s: u32) -> bool {
    return (p.stages & s) != 0u;
}
