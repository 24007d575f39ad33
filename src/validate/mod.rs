//! `sphlab validate`: the validation cases of docs/PHYSICS.md §9 (thesis Chapters 4–5), each run
//! through [`crate::run::run`] and compared with the thesis's reported values and the analytic
//! references (docs/PHYSICS.md §11, `diagnostics::analytic_flows`). Every case writes, under
//! `OUT/<case>/`, the runs (`runs/<id>/series.csv`, `summary.json`, particle snapshots), one SVG
//! per thesis figure and `summary.md` (table `quantity | sphlab | thesis | analytic |
//! difference | verdict` plus the provenance of every run); `validate all` adds `index.md`.
//!
//! `--quick` runs every case at coarse resolution and short times (seconds each): it checks
//! direction and rough size only and is what `tests/validation_quick.rs` runs. `--reuse` takes
//! a run whose `summary.json` says `ok` with exactly the same scene and end time instead of
//! running it again (so long runs started by hand with `sphlab run --out` can be analysed).

pub(crate) mod case;
pub mod data;
pub(crate) mod executor;
mod judge;
pub(crate) mod report;

mod band_rows;
mod capillary_wave;
mod committed;
mod convergence;
mod cross_code;
mod impact;
pub mod oscillation;
mod relax;
mod retime;
mod richardson;
mod scatter;
mod sessile;
mod speed;
mod spurious;
mod wave_band;
mod wave_resolution;

use crate::run::{RunError, RunOptions};
use crate::scene::{builtin, overrides::apply_overrides, Scene};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub use relax::start_sets as relax_start_sets;
pub use report::{Band, CaseReport, Row, RunRecord};

/// The cases, in the order `all` runs them (speed-vs-error reuses oscillation and convergence).
pub const CASES: [&str; 9] = [
    "oscillation",
    "sessile-90",
    "relax-60",
    "convergence",
    "impact",
    "spurious",
    "cross-code",
    "speed-vs-error",
    "capillary-wave",
];

/// The repository's scene files that cases run (by path, as `sphlab run` takes them), embedded
/// so that `validate` runs from any directory.
const SCENE_FILES: [(&str, &str); 1] = [(cross_code::SCENE, include_str!("../../scenes/pysph-rod.toml"))];

/// Options of `sphlab validate`.
#[derive(Clone, Debug)]
pub struct ValidateOptions {
    /// Coarse, short runs (test-suite size).
    pub quick: bool,
    /// The backend of every run.
    pub backend: crate::backend_id::BackendId,
    /// Report root (`reports/validation`).
    pub out: PathBuf,
    /// Reuse matching finished runs.
    pub reuse: bool,
    /// End time of the long sessile/relax/convergence runs (default: the thesis's t = 5).
    pub t_end_long: Option<f64>,
    /// Resolution of the long sessile-90 / relax-60 runs (default: the thesis's 65), with the
    /// capillary rule's p_b and c0 at that resolution.
    pub nx_long: Option<u32>,
    /// With `reuse`: skip (and report) runs that have no finished output instead of running them.
    pub skip_missing: bool,
    /// Run ids to run (reusing or skipping every other one as with `skip_missing`); empty: all.
    pub only: Vec<String>,
    /// Actually run the full-resolution impact (hours per angle on a CPU).
    pub full_impact: bool,
    /// No console lines.
    pub quiet: bool,
    /// Re-apply the verdicts ([`judge`]) to the committed `case.json` instead of measuring
    /// (the measures read particle snapshots, which are not committed).
    pub rejudge: bool,
}

impl Default for ValidateOptions {
    fn default() -> Self {
        Self {
            quick: false,
            backend: crate::backend_id::BackendId::default(),
            out: PathBuf::from("reports/validation"),
            reuse: false,
            t_end_long: None,
            nx_long: None,
            skip_missing: false,
            only: Vec::new(),
            full_impact: false,
            quiet: true,
            rejudge: false,
        }
    }
}

impl ValidateOptions {
    /// End time of the long cases: the thesis's 5 (quick: `quick`).
    pub fn long_t_end(&self, quick: f64) -> f64 {
        if self.quick {
            quick
        } else {
            self.t_end_long.unwrap_or(5.0)
        }
    }

    /// Resolution of the full (not quick) sessile-90 / relax-60 runs: `nx_long` or 65.
    pub fn long_nx(&self) -> u32 {
        self.nx_long.unwrap_or(65)
    }

    /// Overrides of the full sessile-90 / relax-60 runs: none at nx = 65; else the resolution
    /// with the capillary rule's p_b and c0 at it ([`crate::scene::capillary::sets_at`]) and dt
    /// scaled from the scene's (`time.dt_policy = "scale"`).
    pub fn long_sets(&self, scene: &str) -> Vec<String> {
        match self.nx_long {
            Some(nx) if nx != 65 => {
                let base = builtin::builtin(scene).expect("built-in");
                let mut sets = crate::scene::capillary::sets_at(&base, nx);
                sets.push("time.dt_policy=scale".into());
                sets
            }
            _ => vec![],
        }
    }
}

/// Errors of `sphlab validate`.
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    /// Unknown case or bad option (exit 2).
    #[error("{0}")]
    Input(String),
    /// A run failed with a non-blow-up error.
    #[error("run {id}: {err}")]
    Run {
        /// Run id.
        id: String,
        /// The error.
        err: RunError,
    },
    /// `--skip-missing` and no finished run to reuse.
    #[error("run {0}: not run (--skip-missing and no finished run to reuse)")]
    Skipped(String),
    /// Reading or writing a report file.
    #[error("{0}")]
    Io(String),
}

/// One run of a case: a built-in scene (or one of the scene files the cases run) with `--set` overrides (and optionally an edit that
/// overrides cannot express), its end time and snapshot cadence.
#[derive(Clone)]
pub struct RunSpec<'a> {
    /// Run id (directory under `runs/`).
    pub id: String,
    /// Built-in scene name, or the path of a scene file the cases run (`scenes/*.toml`).
    pub base: &'a str,
    /// `KEY=VALUE` overrides.
    pub sets: Vec<String>,
    /// End time (None: the scene's).
    pub t_end: Option<f64>,
    /// Snapshot every N series rows (0: first and last only); the run gets N × `output.every`
    /// steps as its `--every`.
    pub every: u64,
    /// Extra edit, described in `edit_note`.
    pub edit: Option<fn(&mut Scene)>,
    /// What `edit` does, for the report's command line.
    pub edit_note: &'a str,
}

impl<'a> RunSpec<'a> {
    /// A run of `base` with overrides.
    pub fn new(id: impl Into<String>, base: &'a str, sets: &[String], t_end: Option<f64>, every: u64) -> Self {
        RunSpec { id: id.into(), base, sets: sets.to_vec(), t_end, every, edit: None, edit_note: "" }
    }

    /// The scene this spec runs.
    pub fn scene(&self) -> Result<Scene, ValidateError> {
        let base = match builtin::builtin(self.base) {
            Some(s) => s,
            None => {
                let text = SCENE_FILES
                    .iter()
                    .find(|f| f.0 == self.base)
                    .ok_or_else(|| ValidateError::Input(format!("no scene {}", self.base)))?
                    .1;
                Scene::from_toml(text).map_err(|e| ValidateError::Input(format!("{}: {e}", self.base)))?
            }
        };
        let mut s = apply_overrides(&base, &self.sets).map_err(|e| ValidateError::Input(e.to_string()))?;
        if let Some(f) = self.edit {
            f(&mut s);
        }
        Ok(s)
    }

    /// The equivalent command line (for the report).
    pub fn command(&self, dir: &Path) -> String {
        let mut c = format!("sphlab run {}", self.base);
        for s in &self.sets {
            c += &format!(" --set {s}");
        }
        if let Some(t) = self.t_end {
            c += &format!(" --t-end {t}");
        }
        let rows = self.scene().map_or(1, |s| s.output.every);
        c += &format!(" --every {} --out {}", self.every * rows, dir.display());
        if !self.edit_note.is_empty() {
            c += &format!("  [scene edited: {}]", self.edit_note);
        }
        c
    }
}

/// Per-case context: options and the case directory.
pub struct Ctx<'a> {
    /// Options.
    pub opts: &'a ValidateOptions,
    /// `OUT/<case>`.
    pub dir: PathBuf,
}

impl<'a> Ctx<'a> {
    /// The context of `case`.
    pub fn new(opts: &'a ValidateOptions, case: &str) -> Self {
        Ctx { opts, dir: opts.out.join(case) }
    }

    /// Runs a spec into `runs/<id>` (or reuses a matching finished run there or in `also`).
    /// A blow-up is not an error: the record says so and keeps what was written.
    pub fn run(&self, spec: &RunSpec, also: &[PathBuf]) -> Result<RunRecord, ValidateError> {
        let dir = self.dir.join("runs").join(&spec.id);
        let scene = spec.scene()?;
        let mut candidates = vec![dir.clone()];
        candidates.extend(also.iter().cloned());
        let only_other = !self.opts.only.is_empty() && !self.opts.only.contains(&spec.id);
        if self.opts.reuse || only_other {
            for c in &candidates {
                if let Some(rec) = RunRecord::reuse(c, &scene, spec.t_end, &spec.command(c)) {
                    self.say(&format!("  reuse {}", c.display()));
                    return Ok(rec);
                }
            }
        }
        if (self.opts.reuse && self.opts.skip_missing) || only_other {
            return Err(ValidateError::Skipped(spec.id.clone()));
        }
        let opts = RunOptions {
            backend: self.opts.backend,
            t_end: spec.t_end,
            steps: None,
            out: dir.clone(),
            every: spec.every * scene.output.every,
            vtk: false,
            quiet: true,
            ..RunOptions::default()
        };
        self.say(&format!("  run {} ...", spec.command(&dir)));
        let start = Instant::now();
        let status = match crate::run::run(&scene, &opts) {
            Ok(_) => "ok".to_string(),
            Err(RunError::BlowUp(e)) => format!("blow-up: {e}"),
            Err(err) => return Err(ValidateError::Run { id: spec.id.clone(), err }),
        };
        self.say(&format!("  {} {} in {:.1} s", spec.id, status, start.elapsed().as_secs_f64()));
        RunRecord::load(&dir, &spec.command(&dir), false)
            .map(|mut r| {
                r.status = status;
                r
            })
            .ok_or_else(|| ValidateError::Io(format!("{}: no summary.json after the run", dir.display())))
    }

    /// Path of a file in the case directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    fn say(&self, s: &str) {
        if !self.opts.quiet {
            eprintln!("{s}");
        }
    }
}

/// Runs one case (by name) and writes its report.
pub fn run_case(name: &str, opts: &ValidateOptions) -> Result<CaseReport, ValidateError> {
    let ctx = Ctx::new(opts, name);
    std::fs::create_dir_all(&ctx.dir).map_err(|e| ValidateError::Io(format!("{}: {e}", ctx.dir.display())))?;
    if !opts.quiet {
        eprintln!("validate {name}{}", if opts.quick { " (quick)" } else { "" });
    }
    if opts.rejudge {
        return rejudge(name, &ctx);
    }
    let start = Instant::now();
    let mut rep = match name {
        "oscillation" => oscillation::run(&ctx)?,
        "sessile-90" => sessile::run(&ctx)?,
        "relax-60" => relax::run(&ctx)?,
        "convergence" => convergence::run(&ctx)?,
        "impact" => impact::run(&ctx)?,
        "spurious" => spurious::run(&ctx)?,
        "cross-code" => cross_code::run(&ctx)?,
        "speed-vs-error" => speed::run(&ctx)?,
        "capillary-wave" => capillary_wave::run(&ctx)?,
        other => return Err(ValidateError::Input(format!("unknown case `{other}` ({}, all)", CASES.join(", ")))),
    };
    rep.wall_time_s = start.elapsed().as_secs_f64();
    if opts.quick {
        rep.not_full.get_or_insert_with(|| "--quick: coarse resolution and short times".into());
    }
    judge::judge(name, &ctx, &mut rep);
    report::write_summary(&ctx, &rep)?;
    Ok(rep)
}

/// `--rejudge`: the committed `case.json` of `name` with its verdicts applied again (rows, runs
/// and notes as measured; a note says so), written back with its `summary.md` and `index.md`.
fn rejudge(name: &str, ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    let path = ctx.path("case.json");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| ValidateError::Input(format!("--rejudge: {}: {e} (run the case first)", path.display())))?;
    let mut rep: CaseReport =
        serde_json::from_str(&text).map_err(|e| ValidateError::Input(format!("--rejudge: {}: {e}", path.display())))?;
    if CASES.iter().all(|c| *c != name) {
        return Err(ValidateError::Input(format!("unknown case `{name}` ({}, all)", CASES.join(", "))));
    }
    let head = format!("Verdicts applied by `sphlab validate {name} --rejudge`");
    rep.notes.retain(|n| !n.starts_with(&head));
    rep.notes.push(format!("{head} to the rows as measured from the runs below (no run or measure repeated)."));
    judge::judge(name, ctx, &mut rep);
    report::write_summary(ctx, &rep)?;
    Ok(rep)
}

/// Runs every case and writes `index.md`. A case that fails is listed with its error.
pub fn run_all(opts: &ValidateOptions) -> Result<Vec<CaseReport>, ValidateError> {
    let mut reps = Vec::new();
    let mut failed = Vec::new();
    for c in CASES {
        match run_case(c, opts) {
            Ok(r) => reps.push(r),
            // Ctrl-C stops the whole validation, not just this case.
            Err(e @ ValidateError::Run { err: RunError::Interrupted { .. }, .. }) => return Err(e),
            Err(e) => failed.push((c.to_string(), e.to_string())),
        }
    }
    report::write_index(opts, &reps, &failed)?;
    Ok(reps)
}
