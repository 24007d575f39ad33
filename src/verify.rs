//! `sphlab verify`: judges every GPU variant against the CPU reference of the same precision.
//!
//! 1. **One force evaluation** on the scene's initial state (velocity field applied, no
//!    relaxation): per field (colour and mass exactly; σ, χ, ρ, p, ∇C, Π, acceleration, ṽ) the
//!    max error relative to the field's scale and the relative L2 error ([`field_error`]),
//!    against [`TOLERANCES`]; contact points too. The GPU tests use the same measure and table.
//! 2. **After N steps**: the scene's observables (liquid kinetic energy, centroid, contact angle,
//!    spread factor) against the CPU run, and the exact invariants (particle count, mass per phase).
//! 3. **Per stage** (`--per-stage`): each GPU stage alone on the CPU's inputs for that stage
//!    (`GpuSolver::run_stage_from`, outputs poisoned first), to pinpoint a disagreeing stage.

use crate::backend::{Backend, Frame};
use crate::cpu::CpuSolver;
use crate::exec::Exec;
use crate::fields::{Field, Fields};
use crate::gpu::solver::GpuSolver;
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::model::Model;
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::real::Real;
use crate::real::V2;
use crate::run::measure;
use crate::scene::build::{build_layout, Layout};
use crate::scene::initial::initial_velocities;
use crate::scene::Scene;
use crate::stage::Stage;
use serde::Serialize;
use std::cell::OnceCell;
use std::sync::Arc;

/// A field with its (max-rel, rel-L2) bounds for f64 and for f32.
pub type Tolerance = (Field, (f64, f64), (f64, f64));

/// Per-field tolerances of one evaluation, `(field, f32 (max-rel, rel-L2), f64 (max-rel, rel-L2))`,
/// the one table `sphlab verify` and the GPU tests use. Errors are measured by [`field_error`]
/// against the field's largest CPU magnitude (the pressure against at least the EOS scale B:
/// its terms cancel near ρ0). Both sides run the same formulas in the same precision; they
/// differ only in summation order (cell, candidate and list orders, atomics in any order), fused
/// multiply-adds and WGSL's 2.5-ulp division and square root. σ, χ and ρ are sums of positive
/// terms (a few ulp); p inherits ρ's error times γ; ∇C, Π and the acceleration are sums of ~30
/// terms of both signs that cancel to a small fraction of their size (the pressure term with
/// p_b = B cancels to ~1e-3), so the reordering error of the large terms shows at 1e-4–1e-3 of
/// the result's scale in f32. The acceleration's rel-L2 bound is 3e-4: at the impact scene's
/// density ratio of 833 the gas particles' pressure and viscous terms cancel further, and every
/// f32 variant (direct and cells alike, whose f64 twins agree to 1e-12) measures 1.2–1.6e-4 there
/// from summation order alone. Colours and masses are copied
/// or typed, never summed: exact.
pub const TOLERANCES: &[Tolerance] = &[
    (Field::Colour, (0.0, 0.0), (0.0, 0.0)),
    (Field::Mass, (0.0, 0.0), (0.0, 0.0)),
    (Field::Sigma, TOL_SUM, TOL_F64),
    (Field::Chi, TOL_SUM, TOL_F64),
    (Field::Rho, TOL_SUM, TOL_F64),
    (Field::P, TOL_SUM, TOL_F64),
    (Field::Grad, TOL_SUM, TOL_F64),
    (Field::Pi, TOL_SUM, TOL_F64),
    (Field::Acc, TOL_ACC, TOL_F64),
    (Field::Vt, TOL_SUM, TOL_F64),
];
const TOL_SUM: (f64, f64) = (1e-4, 1e-5);
const TOL_ACC: (f64, f64) = (1e-3, 3e-4);
const TOL_F64: (f64, f64) = (1e-9, 1e-9);
/// Contact points: position error relative to max(|r|, Δx) plus the side difference.
pub const CONTACT_TOLERANCE: f64 = 1e-5;

/// The `(max-rel, rel-L2)` tolerance of `field` in precision `T`, if the table compares it.
pub fn tolerance<T: Real>(field: Field) -> Option<(f64, f64)> {
    TOLERANCES.iter().find(|t| t.0 == field).map(|t| if T::NAME == "f64" { t.2 } else { t.1 })
}

/// The floor of a field's error scale: the EOS scale B = max(stiffness + |p_b|) for the
/// pressure, 0 otherwise.
pub fn scale_floor<T: Real>(field: Field, model: &Model<T>) -> f64 {
    match field {
        Field::P => model.phases.iter().map(|p| (p.stiffness + p.p_b.abs()).f64()).fold(0.0, f64::max),
        _ => 0.0,
    }
}

/// Observable tolerances after N steps: `(name, tolerance, unit)`. Trajectories of two summation
/// orders drift apart slowly; over 50 steps the observables agree far below these bounds.
pub const OBS_TOLERANCES: &[(&str, f64, &str)] = &[
    ("kinetic_energy", 1e-2, "relative"),
    ("centroid_x", 1e-3, "Δx"),
    ("centroid_y", 1e-3, "Δx"),
    ("theta_circle_fit", 0.5, "degrees"),
    ("spread_factor", 5e-3, "absolute"),
    ("wave_amplitude", 1e-3, "Δx"),
];

/// One compared quantity.
#[derive(Clone, Debug, Serialize)]
pub struct Check {
    /// field, contacts, observable, invariant or stage.
    pub kind: String,
    /// Field or observable name (stage checks: `stage:field`).
    pub name: String,
    /// Max error relative to the field scale (fields) or the difference (observables).
    pub max_rel: f64,
    /// Relative L2 error (fields); NaN otherwise.
    pub rel_l2: f64,
    /// The tolerance on `max_rel`.
    pub tolerance: f64,
    /// Passed.
    pub pass: bool,
}

/// The verdict on one variant.
#[derive(Clone, Debug, Serialize)]
pub struct VariantReport {
    /// Variant id.
    pub variant: String,
    /// The variant as it ran (its list format resolved by N: `.slots` or `.masks` where the
    /// format is a choice); empty when it did not run.
    pub ran: String,
    /// pass, FAIL, unsupported, error or skipped (not run: `verify --budget` spent).
    pub status: String,
    /// Why unsupported / what failed.
    pub reason: String,
    /// Every check.
    pub checks: Vec<Check>,
    /// The list chunks its slot arrays took (`gpu::list_chunks`; 1 unless they passed the
    /// per-buffer limit, 0 when it did not run).
    pub list_chunks: usize,
}

impl VariantReport {
    /// A variant that was not run (`status`: skipped, unsupported or error), and why.
    pub fn not_run(variant: String, status: &str, reason: String) -> Self {
        let (ran, checks) = (String::new(), Vec::new());
        VariantReport { variant, ran, status: status.into(), reason, checks, list_chunks: 0 }
    }

    /// A variant that was not run, and why.
    pub fn skipped(variant: VariantSpec, reason: String) -> Self {
        Self::not_run(variant.to_string(), "skipped", reason)
    }
}

/// The one error measure: (max |gpu − cpu| / scale, ‖gpu − cpu‖₂ / ‖cpu‖₂) with scale =
/// max(max |cpu|, `floor`); a non-finite difference (NaN poison left in place) or a length
/// mismatch is infinite; identical vectors are (0, 0).
pub fn field_error(gpu: &[f64], cpu: &[f64], floor: f64) -> (f64, f64) {
    if gpu.len() != cpu.len() {
        return (f64::INFINITY, f64::INFINITY);
    }
    let scale = cpu.iter().fold(floor, |m, v| m.max(v.abs()));
    let (mut dmax, mut d2, mut r2) = (0.0f64, 0.0, 0.0);
    for (a, b) in gpu.iter().zip(cpu) {
        let d = if a == b { 0.0 } else { a - b };
        if !d.is_finite() {
            return (f64::INFINITY, f64::INFINITY);
        }
        dmax = dmax.max(d.abs());
        d2 += d * d;
        r2 += b * b;
    }
    if dmax == 0.0 {
        return (0.0, 0.0);
    }
    if scale == 0.0 {
        return (f64::INFINITY, f64::INFINITY);
    }
    (dmax / scale, (d2 / r2.max(scale * scale * 1e-30)).sqrt())
}

/// Compares every field of one evaluation of `model`'s scene (and the contact points) against
/// [`TOLERANCES`]; `only` restricts the fields (a stage's outputs).
pub fn compare_fields<T: Real>(
    kind: &str,
    prefix: &str,
    gpu: &Fields<T>,
    cpu: &Fields<T>,
    model: &Model<T>,
    n_fluid: usize,
    only: Option<&[Field]>,
) -> Vec<Check> {
    let mut out = Vec::new();
    let check = |name: String, max_rel: f64, rel_l2: f64, (tmax, tl2): (f64, f64)| Check {
        kind: kind.into(),
        name,
        max_rel,
        rel_l2,
        tolerance: tmax,
        pass: max_rel <= tmax && (rel_l2 <= tl2 || tl2 == f64::INFINITY),
    };
    for &field in Field::ALL.iter().filter(|f| only.is_none_or(|o| o.contains(f))) {
        let name = format!("{prefix}{}", field.name());
        if field == Field::Contacts {
            let same_count = gpu.contacts.len() == cpu.contacts.len();
            let worst = gpu
                .contacts
                .iter()
                .zip(&cpu.contacts)
                .map(|(a, b)| ((a.r - b.r).norm() / b.r.norm().max(model.dx)).f64() + (a.s - b.s).abs().f64())
                .fold(if same_count { 0.0 } else { f64::INFINITY }, f64::max);
            // The cos θ_d measured at each point (the unbalanced Young force; both empty otherwise).
            let same_cos = gpu.contact_cos.len() == cpu.contact_cos.len();
            let worst = gpu
                .contact_cos
                .iter()
                .zip(&cpu.contact_cos)
                .map(|(a, b)| (*a - *b).abs().f64())
                .fold(if same_cos { worst } else { f64::INFINITY }, f64::max);
            out.push(check(name, worst, f64::NAN, (CONTACT_TOLERANCE, f64::INFINITY)));
        } else if let Some(tol) = tolerance::<T>(field) {
            let floor = scale_floor(field, model);
            let (m, l2) = field_error(&gpu.flat(field, n_fluid), &cpu.flat(field, n_fluid), floor);
            out.push(check(name, m, l2, tol));
        }
    }
    out
}

/// The observables of `scene` ([`OBS_TOLERANCES`]) and the exact invariants of frame `g` against
/// frame `c` after the same steps.
pub fn observables(scene: &Scene, g: &Frame, c: &Frame) -> Vec<Check> {
    let (rg, rc) = (measure(scene, g), measure(scene, c));
    let dx = scene.domain.dx();
    let mut out = Vec::new();
    for &(name, tol, _) in OBS_TOLERANCES {
        let (a, b) = match name {
            "kinetic_energy" => (Some(rg.kinetic_energy), Some(rc.kinetic_energy)),
            "centroid_x" => (Some(rg.centroid_x), Some(rc.centroid_x)),
            "centroid_y" => (Some(rg.centroid_y), Some(rc.centroid_y)),
            "theta_circle_fit" => (rg.theta_circle_fit, rc.theta_circle_fit),
            "wave_amplitude" => (rg.wave_amplitude, rc.wave_amplitude),
            _ => (rg.spread_factor, rc.spread_factor),
        };
        let (Some(a), Some(b)) = (a, b) else { continue };
        if !(b.is_finite()) {
            continue;
        }
        let d = match name {
            "kinetic_energy" => (a - b).abs() / b.abs().max(1e-300),
            "centroid_x" | "centroid_y" | "wave_amplitude" => (a - b).abs() / dx,
            _ => (a - b).abs(),
        };
        out.push(Check {
            kind: "observable".into(),
            name: name.into(),
            max_rel: d,
            rel_l2: f64::NAN,
            tolerance: tol,
            pass: d <= tol,
        });
    }
    let count = (g.pos.len() == c.pos.len() && g.n_fluid == c.n_fluid) as u8 as f64;
    out.push(Check {
        kind: "invariant".into(),
        name: "particle_count".into(),
        max_rel: 1.0 - count,
        rel_l2: f64::NAN,
        tolerance: 0.0,
        pass: count == 1.0,
    });
    for (k, (a, b)) in [(rg.mass_phase0, rc.mass_phase0), (rg.mass_phase1, rc.mass_phase1)].into_iter().enumerate() {
        out.push(Check {
            kind: "invariant".into(),
            name: format!("mass_phase{k}"),
            max_rel: (a - b).abs(),
            rel_l2: f64::NAN,
            tolerance: 0.0,
            pass: a == b,
        });
    }
    out
}

/// The CPU side of a verification, computed once per precision and shared by every variant
/// checked against it: the fields of the first evaluation (and each stage's, for `--per-stage`),
/// the initial positions and velocities, and the frame after the observable steps.
struct CpuReference<T: Real> {
    fields: Fields<T>,
    model: Model<T>,
    n_fluid: usize,
    stagewise: Vec<(Stage, Fields<T>)>,
    pos: Vec<V2<T>>,
    vel: Vec<V2<T>>,
    frame: Frame,
}

impl<T: Real> CpuReference<T> {
    fn new(scene: &Scene, layout: &Layout, vel0: &[[f64; 2]], steps: u64) -> Result<Self, String> {
        let mut cpu = CpuSolver::<T>::new(scene, layout, Exec::Parallel, SearchKind::Cells);
        cpu.restart_with_velocities(vel0);
        let stagewise = cpu.evaluate_stagewise().map_err(|e| e.to_string())?;
        let (fields, pos, vel) = (cpu.f.clone(), cpu.pos.clone(), cpu.vel.clone());
        for _ in 0..steps {
            cpu.advance().map_err(|e| format!("CPU: {e}"))?;
        }
        let frame = cpu.frame();
        Ok(Self { fields, model: cpu.model.clone(), n_fluid: cpu.n_fluid, stagewise, pos, vel, frame })
    }
}

/// Verifies variants on one scene: the layout and the CPU reference of each precision are built
/// once (on first use) and shared by every variant.
pub struct Verifier {
    scene: Scene,
    layout: Result<Layout, String>,
    vel0: Vec<[f64; 2]>,
    steps: u64,
    per_stage: bool,
    f32: OnceCell<Result<CpuReference<f32>, String>>,
    f64: OnceCell<Result<CpuReference<f64>, String>>,
}

impl Verifier {
    /// A verifier of `scene` (relaxation is skipped: the initial state is compared) over `steps`
    /// steps, each stage alone too when `per_stage`.
    pub fn new(scene: &Scene, steps: u64, per_stage: bool) -> Self {
        let mut scene = scene.clone();
        scene.relax = None;
        let layout = build_layout(&scene).map_err(|e| e.to_string());
        let vel0 = layout.as_ref().map(|l| initial_velocities(&scene, l, None)).unwrap_or_default();
        Verifier { scene, layout, vel0, steps, per_stage, f32: OnceCell::new(), f64: OnceCell::new() }
    }

    /// The report of one variant.
    pub fn variant(&self, ctx: &Arc<GpuContext>, spec: VariantSpec) -> VariantReport {
        self.variant_on(ctx, spec, None)
    }

    /// The report of one variant whose GPU side runs `gpu_scene` (same layout; `None`: the
    /// verifier's scene) against the CPU reference of the verifier's scene: a variant given a
    /// perturbed constant on purpose must fail.
    pub fn variant_on(&self, ctx: &Arc<GpuContext>, spec: VariantSpec, gpu_scene: Option<&Scene>) -> VariantReport {
        let variant = spec.to_string();
        if let Err(reason) = spec.support(ctx) {
            return VariantReport::not_run(variant, "unsupported", reason);
        }
        let layout = match &self.layout {
            Ok(l) => l,
            Err(e) => return VariantReport::not_run(variant, "error", e.clone()),
        };
        let (scene, vel0, steps) = (&self.scene, &self.vel0[..], self.steps);
        let gpu_scene = gpu_scene.map(|s| Scene { relax: None, ..s.clone() });
        let gpu_scene = gpu_scene.as_ref();
        let r = match spec.precision {
            Precision::F32 => match self.f32.get_or_init(|| CpuReference::new(scene, layout, vel0, steps)) {
                Ok(c) => self.typed(ctx, layout, spec, c, gpu_scene.unwrap_or(scene)),
                Err(e) => Err(e.clone()),
            },
            Precision::F64 => match self.f64.get_or_init(|| CpuReference::new(scene, layout, vel0, steps)) {
                Ok(c) => self.typed(ctx, layout, spec, c, gpu_scene.unwrap_or(scene)),
                Err(e) => Err(e.clone()),
            },
        };
        match r {
            Ok((checks, ran, list_chunks)) => {
                let failed: Vec<String> = checks.iter().filter(|c| !c.pass).map(|c| c.name.clone()).collect();
                let status = if failed.is_empty() { "pass" } else { "FAIL" };
                VariantReport { variant, ran, status: status.into(), reason: failed.join(", "), checks, list_chunks }
            }
            Err(e) => VariantReport::not_run(variant, "error", e),
        }
    }

    fn typed<T: Real>(
        &self,
        ctx: &Arc<GpuContext>,
        layout: &Layout,
        spec: VariantSpec,
        cpu: &CpuReference<T>,
        gpu_scene: &Scene,
    ) -> Result<(Vec<Check>, String, usize), String> {
        let mut gpu = GpuSolver::<T>::new(ctx.clone(), gpu_scene, layout, spec).map_err(|e| e.to_string())?;
        gpu.restart_with_velocities(&self.vel0);
        let nf = cpu.n_fluid;
        gpu.evaluate_once().map_err(|e| e.to_string())?;
        let gf = gpu.read_fields().map_err(|e| e.to_string())?;
        let mut checks = compare_fields("field", "", &gf, &cpu.fields, &cpu.model, nf, None);
        if self.per_stage {
            for w in cpu.stagewise.windows(2) {
                let ((_, before), (stage, after)) = (&w[0], &w[1]);
                let outputs: Vec<Field> = stage.outputs().collect();
                if outputs.is_empty() {
                    continue;
                }
                match gpu.run_stage_from(&cpu.pos, &cpu.vel, before, *stage) {
                    Ok(g) => {
                        let c =
                            compare_fields("stage", &format!("{stage}:"), &g, after, &cpu.model, nf, Some(&outputs));
                        checks.extend(c)
                    }
                    Err(e) => checks.push(Check {
                        kind: "stage".into(),
                        name: format!("{stage}: {e}"),
                        max_rel: f64::INFINITY,
                        rel_l2: f64::NAN,
                        tolerance: 0.0,
                        pass: false,
                    }),
                }
            }
            gpu.restart_with_velocities(&self.vel0);
        }
        // The GPU takes all its steps in one submission (the device clock, adaptive dt and check).
        Backend::advance(&mut gpu, self.steps).map_err(|e| format!("GPU: {e}"))?;
        checks.extend(observables(&self.scene, &gpu.frame(), &cpu.frame));
        Ok((checks, gpu.spec().to_string(), gpu.list_chunks()))
    }
}

/// A terminal table: one line per variant (as it ran: its list format resolved) with its worst field
/// and observable.
pub fn format_table(reports: &[VariantReport]) -> String {
    let mut s = format!(
        "{:<44} {:<11} {:>9} {:>9} {:>9} {:>9}  {}\n",
        "variant", "status", "σ relL2", "p relL2", "acc max", "acc relL2", "notes"
    );
    for r in reports {
        let get = |f: Field| r.checks.iter().find(|c| c.name == f.name());
        let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2e}"));
        s += &format!(
            "{:<44} {:<11} {:>9} {:>9} {:>9} {:>9}  {}\n",
            if r.ran.is_empty() { &r.variant } else { &r.ran },
            r.status,
            f(get(Field::Sigma).map(|c| c.rel_l2)),
            f(get(Field::P).map(|c| c.rel_l2)),
            f(get(Field::Acc).map(|c| c.max_rel)),
            f(get(Field::Acc).map(|c| c.rel_l2)),
            if r.list_chunks > 1 { format!("{} list chunks {}", r.list_chunks, r.reason) } else { r.reason.clone() }
        );
    }
    s
}

/// Writes `verify.csv` (one row per check, with the adapter, scene, commit and date) into `dir`;
/// `verify.json` is written by the caller as the one enveloped document of `verify --json`.
pub fn write_outputs(
    dir: &std::path::Path,
    adapter: &str,
    scene: &Scene,
    reports: &[VariantReport],
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let (commit, date) = (crate::output::git_commit(), crate::output::now_utc_iso8601());
    let path = dir.join("verify.csv");
    let mut w = csv::Writer::from_path(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    w.write_record([
        "variant",
        "status",
        "kind",
        "check",
        "max_rel",
        "rel_l2",
        "tolerance",
        "pass",
        "scene",
        "adapter",
        "commit",
        "date",
    ])
    .map_err(|e| e.to_string())?;
    for r in reports {
        let rows: Vec<Check> = if r.checks.is_empty() {
            vec![Check {
                kind: "-".into(),
                name: r.reason.clone(),
                max_rel: f64::NAN,
                rel_l2: f64::NAN,
                tolerance: f64::NAN,
                pass: r.status != "FAIL" && r.status != "error",
            }]
        } else {
            r.checks.clone()
        };
        for c in rows {
            w.write_record([
                r.variant.as_str(),
                r.status.as_str(),
                c.kind.as_str(),
                c.name.as_str(),
                &format!("{:e}", c.max_rel),
                &format!("{:e}", c.rel_l2),
                &format!("{:e}", c.tolerance),
                if c.pass { "true" } else { "false" },
                scene.name.as_str(),
                adapter,
                commit.as_str(),
                date.as_str(),
            ])
            .map_err(|e| e.to_string())?;
        }
    }
    // verify.json is the caller's: one enveloped document shared with `verify --json`.
    w.flush().map_err(|e| e.to_string())
}
