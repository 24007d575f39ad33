//! The `sphlab` command line: `run`, `scene`, `analytic` (and, as they land, `variants`,
//! `verify`, `validate`, `study`). Bad input exits 2 with a message naming what is wrong; a run
//! that blows up exits 3 with the step and particle named.

use clap::{Args, Parser, Subcommand};
use sphlab::neighbours::SearchKind;
use sphlab::run::{RunError, RunOptions};
use sphlab::scene::{builtin, overrides::apply_overrides, Scene};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "sphlab", version, about = "GPU-vs-CPU performance laboratory for 2D multiphase SPH")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a scene (built-in name or TOML file) and write series.csv, snapshots and summary.json.
    Run(RunArgs),
    /// Built-in scenes.
    Scene {
        #[command(subcommand)]
        cmd: SceneCmd,
    },
    /// List the GPU variants, what each needs, and whether this adapter runs it.
    Variants,
    /// Check GPU variants against the CPU reference (fields, stages, observables).
    Verify(VerifyArgs),
    /// The Chapter 6 timing study: E1 (search × backend), E4 (speedup), scaling; records.csv + summary.md.
    Study(StudyArgs),
    /// Validation cases against the thesis and analytic references (reports/validation).
    Validate(ValidateArgs),
    /// Analytic drop-spread models (thesis §5.1, Table 1).
    Analytic {
        #[command(subcommand)]
        cmd: AnalyticCmd,
    },
}

#[derive(Args)]
struct RunArgs {
    /// Built-in scene name (see `sphlab scene list`) or a scene TOML file.
    #[arg(default_value = "oscillating-drop")]
    scene: String,
    /// cpu (all cores), cpu1 (one thread) or gpu.
    #[arg(long, default_value = "cpu")]
    backend: String,
    /// GPU variant id (see `sphlab variants`).
    #[arg(long)]
    variant: Option<String>,
    /// f64 or f32 (CPU backends).
    #[arg(long, default_value = "f64")]
    precision: String,
    /// End time (overrides the scene's time.t_end).
    #[arg(long, conflicts_with = "steps")]
    t_end: Option<f64>,
    /// Run exactly N steps.
    #[arg(long)]
    steps: Option<u64>,
    /// Override a scene field by its TOML path, e.g. `--set contact.theta_deg=60`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// A particle snapshot every N series rows (0: only the first and the last).
    #[arg(long, default_value_t = 10)]
    every: u64,
    /// Also write VTK (.vtu + .pvd) snapshots.
    #[arg(long)]
    vtk: bool,
    /// CPU neighbour search: direct, cells or tracking.
    #[arg(long, default_value = "cells")]
    search: String,
    /// No progress bar or console lines.
    #[arg(long)]
    quiet: bool,
}

#[derive(Args)]
struct VerifyArgs {
    /// Built-in scene name or a scene TOML file.
    #[arg(default_value = "oscillating-drop")]
    scene: String,
    /// `all` or a comma-separated list of variant ids.
    #[arg(long, default_value = "all")]
    variants: String,
    /// Steps for the observable comparison.
    #[arg(long, default_value_t = 50)]
    steps: u64,
    /// Override a scene field by its TOML path.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
    /// Also run every stage alone on the CPU's inputs (pinpoints a disagreeing stage).
    #[arg(long)]
    per_stage: bool,
    /// Write verify.csv and verify.json here.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Args)]
struct StudyArgs {
    /// Experiments: e1, e4, scaling (comma-separated) or all.
    #[arg(long, default_value = "all")]
    experiments: String,
    /// Scaling resolutions (particles across the box).
    #[arg(long, default_value = "30,60,120")]
    sizes: String,
    /// Timed steps per backend.
    #[arg(long, default_value_t = 10)]
    steps: u64,
    /// GPU variants: `all` or comma-separated ids.
    #[arg(long, default_value = "all")]
    variants: String,
    /// Output directory.
    #[arg(long, default_value = "reports/study")]
    out: PathBuf,
}

#[derive(Args)]
struct ValidateArgs {
    /// oscillation, sessile-90, relax-60, convergence, impact, spurious, speed-vs-error or all.
    case: String,
    /// Coarse resolution and short times (seconds per case; direction and rough size only).
    #[arg(long)]
    quick: bool,
    /// cpu, cpu1 or gpu.
    #[arg(long, default_value = "cpu")]
    backend: String,
    /// GPU variant id.
    #[arg(long)]
    variant: Option<String>,
    /// f64 or f32.
    #[arg(long, default_value = "f64")]
    precision: String,
    /// Report directory.
    #[arg(long, default_value = "reports/validation")]
    out: PathBuf,
    /// Reuse finished runs of exactly the same scene and end time found in the report directory.
    #[arg(long)]
    reuse: bool,
    /// With --reuse: skip runs that have no finished output (they are listed as not run).
    #[arg(long, requires = "reuse")]
    skip_missing: bool,
    /// Run only these run ids (comma-separated, e.g. `nx45,nx65`); every other run is reused if
    /// finished, else skipped and listed.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// End time of the long sessile-90 / relax-60 / convergence runs (default: the thesis's 5).
    #[arg(long)]
    t_end: Option<f64>,
    /// Resolution of the long sessile-90 / relax-60 runs (default: the thesis's 65; p_b follows
    /// the built-ins' rule σ/(2Δx) at that resolution).
    #[arg(long)]
    nx_long: Option<u32>,
    /// Run the impact case at full resolution (hours per angle on a CPU).
    #[arg(long)]
    full_impact: bool,
    /// No console lines.
    #[arg(long)]
    quiet: bool,
}

#[derive(Subcommand)]
enum SceneCmd {
    /// List the built-in scenes.
    List,
    /// Print a built-in scene as TOML (edit it and pass the file to `sphlab run`).
    Show {
        /// Scene name.
        name: String,
    },
}

#[derive(Subcommand)]
enum AnalyticCmd {
    /// Maximum spread D_max/D0 of every model for one impact.
    Spread {
        /// Reynolds number ρV0D0/μ.
        #[arg(long)]
        re: f64,
        /// Weber number ρV0²D0/σ.
        #[arg(long)]
        we: f64,
        /// Contact angle in degrees.
        #[arg(long, conflicts_with = "theta_rad", required_unless_present = "theta_rad")]
        theta_deg: Option<f64>,
        /// Contact angle in radians.
        #[arg(long)]
        theta_rad: Option<f64>,
        /// all, axisym, a, b or c.
        #[arg(long, default_value = "all")]
        model: String,
        /// JSON output.
        #[arg(long)]
        json: bool,
    },
    /// The thesis's Table 1 beside sphlab's values, with the relative error of each cell.
    Table1 {
        /// JSON output.
        #[arg(long)]
        json: bool,
    },
}

/// Loads a scene by built-in name or TOML path, then applies `--set` overrides.
fn load_scene(name: &str, sets: &[String]) -> Result<Scene, String> {
    let base = if let Some(s) = builtin::builtin(name) {
        s
    } else if std::path::Path::new(name).exists() {
        let text = std::fs::read_to_string(name).map_err(|e| format!("cannot read scene file {name}: {e}"))?;
        Scene::from_toml(&text).map_err(|e| format!("{name}: {e}"))?
    } else {
        return Err(format!(
            "unknown scene `{name}`: not a built-in ({}) and no such file",
            builtin::BUILTIN.join(", ")
        ));
    };
    apply_overrides(&base, sets).map_err(|e| e.to_string())
}

fn fail(code: u8, msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {msg}");
    ExitCode::from(code)
}

fn cmd_run(a: RunArgs) -> ExitCode {
    let scene = match load_scene(&a.scene, &a.sets) {
        Ok(s) => s,
        Err(e) => return fail(2, e),
    };
    let Some(search) = SearchKind::parse(&a.search) else {
        return fail(2, format!("--search: unknown search `{}` (direct, cells, tracking)", a.search));
    };
    let opts = RunOptions {
        backend: a.backend,
        variant: a.variant,
        precision: a.precision,
        t_end: a.t_end,
        steps: a.steps,
        out: a.out,
        every: a.every,
        vtk: a.vtk,
        search,
        quiet: a.quiet,
    };
    match sphlab::run::run(&scene, &opts) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e @ RunError::BlowUp(_)) => fail(3, format!("{e}; outputs so far are in {}", opts.out.display())),
        Err(e) => fail(e.exit_code() as u8, e),
    }
}

fn cmd_validate(a: ValidateArgs) -> ExitCode {
    use sphlab::validate::{self, ValidateError, ValidateOptions};
    if a.t_end.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
        return fail(2, "--t-end: must be positive");
    }
    let opts = ValidateOptions {
        quick: a.quick,
        backend: a.backend,
        variant: a.variant,
        precision: a.precision,
        out: a.out,
        reuse: a.reuse,
        skip_missing: a.skip_missing,
        only: a.only,
        t_end_long: a.t_end,
        nx_long: a.nx_long,
        full_impact: a.full_impact,
        quiet: a.quiet,
    };
    let res = if a.case == "all" {
        validate::run_all(&opts).map(|r| r.len())
    } else {
        validate::run_case(&a.case, &opts).map(|_| 1)
    };
    match res {
        Ok(n) => {
            if !opts.quiet {
                eprintln!("{n} case(s) written under {}", opts.out.display());
            }
            ExitCode::SUCCESS
        }
        Err(e @ ValidateError::Input(_)) => fail(2, e),
        Err(e) => fail(1, e),
    }
}

fn cmd_analytic(cmd: AnalyticCmd) -> ExitCode {
    use sphlab::analytic;
    match cmd {
        AnalyticCmd::Spread { re, we, theta_deg, theta_rad, model, json } => {
            let theta = theta_rad.unwrap_or_else(|| theta_deg.unwrap_or(f64::NAN).to_radians());
            if !["all", "axisym", "a", "b", "c"].contains(&model.as_str()) {
                return fail(2, format!("--model: unknown model `{model}` (all, axisym, a, b, c)"));
            }
            let r = match analytic::spread_all(re, we, theta) {
                Ok(r) => r,
                Err(e) => return fail(2, e),
            };
            if json {
                let v = serde_json::to_value(&r).expect("serialisable");
                let v = match model.as_str() {
                    "axisym" => serde_json::json!({"model": "axisym", "xi": r.axisym}),
                    "a" => serde_json::json!({"model": "a", "xi": r.model_a}),
                    "b" => serde_json::json!({"model": "b", "xi": r.model_b}),
                    "c" => serde_json::json!({"model": "c", "xi": r.model_c}),
                    _ => v,
                };
                println!("{}", serde_json::to_string_pretty(&v).expect("json"));
            } else {
                match model.as_str() {
                    "axisym" => println!("D_max/D0 (axisymmetric) = {:.4}", r.axisym),
                    "a" => println!("D_max/D0 (2D a) = {:.4}", r.model_a),
                    "b" => println!("D_max/D0 (2D b) = {:.4}", r.model_b),
                    "c" => println!("D_max/D0 (2D c, eq. 93) = {:.4}", r.model_c),
                    _ => print!("{}", analytic::format_spread(&r)),
                }
            }
            ExitCode::SUCCESS
        }
        AnalyticCmd::Table1 { json } => {
            let rows = analytic::table1_comparison();
            if json {
                println!("{}", serde_json::to_string_pretty(&rows).expect("json"));
            } else {
                print!("{}", analytic::format_table1(&rows));
            }
            ExitCode::SUCCESS
        }
    }
}

fn gpu_context() -> Result<std::sync::Arc<sphlab::gpu::GpuContext>, String> {
    sphlab::gpu::GpuContext::new().map(std::sync::Arc::new).map_err(|e| e.to_string())
}

fn cmd_variants() -> ExitCode {
    use sphlab::gpu::variant::VariantSpec;
    let ctx = gpu_context();
    match &ctx {
        Ok(c) => println!("adapter: {}", c.describe()),
        Err(e) => println!("adapter: none ({e})"),
    }
    for v in VariantSpec::all() {
        let status = match (&ctx, v.implemented()) {
            (_, Err(e)) => format!("unsupported: {e}"),
            (Err(_), Ok(())) => "unknown: no adapter".to_string(),
            (Ok(c), Ok(())) => match v.support(c) {
                Ok(()) => "supported".to_string(),
                Err(e) => format!("unsupported: {e}"),
            },
        };
        let mut needs = vec![];
        if v.precision == sphlab::gpu::variant::Precision::F64 {
            needs.push("SHADER_F64");
        }
        if v.accumulation == sphlab::gpu::variant::Accumulation::Native {
            needs.push("SHADER_FLOAT32_ATOMIC");
        }
        let needs = if needs.is_empty() { "-".to_string() } else { needs.join("+") };
        println!("{:<44} needs {:<34} {status}", v.to_string(), needs);
    }
    ExitCode::SUCCESS
}

fn cmd_verify(a: VerifyArgs) -> ExitCode {
    use sphlab::gpu::variant::VariantSpec;
    let scene = match load_scene(&a.scene, &a.sets) {
        Ok(s) => s,
        Err(e) => return fail(2, e),
    };
    let specs: Vec<VariantSpec> = if a.variants == "all" {
        VariantSpec::all()
    } else {
        let mut v = Vec::new();
        for id in a.variants.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match id.parse() {
                Ok(s) => v.push(s),
                Err(e) => return fail(2, format!("--variants: {e}")),
            }
        }
        v
    };
    let ctx = match gpu_context() {
        Ok(c) => c,
        Err(e) => return fail(2, format!("no GPU adapter: {e}")),
    };
    if !a.json {
        eprintln!("adapter: {}; scene {}; {} variants; {} steps", ctx.describe(), scene.name, specs.len(), a.steps);
    }
    let mut reports = Vec::new();
    for spec in specs {
        let r = sphlab::verify::verify_variant(&ctx, &scene, spec, a.steps, a.per_stage);
        if !a.json {
            eprintln!("{} {}", r.variant, r.status);
        }
        reports.push(r);
    }
    let failed = reports.iter().any(|r| r.status == "FAIL" || r.status == "error");
    if let Some(dir) = &a.out {
        if let Err(e) = sphlab::verify::write_outputs(dir, &ctx.describe(), &scene, &reports) {
            return fail(1, e);
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&reports).expect("json"));
    } else {
        print!("{}", sphlab::verify::format_table(&reports));
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

fn cmd_study(a: StudyArgs) -> ExitCode {
    let experiments: Vec<String> = if a.experiments == "all" {
        vec!["e1".into(), "e4".into(), "scaling".into()]
    } else {
        a.experiments.split(',').map(|s| s.trim().to_string()).collect()
    };
    let mut sizes = Vec::new();
    for s in a.sizes.split(',') {
        match s.trim().parse::<u32>() {
            Ok(n) if n >= 10 => sizes.push(n),
            _ => return fail(2, format!("--sizes: `{s}` is not a resolution ≥ 10")),
        }
    }
    if a.steps == 0 {
        return fail(2, "--steps: must be at least 1");
    }
    let mut variants = Vec::new();
    if a.variants != "all" {
        for id in a.variants.split(',') {
            match id.trim().parse() {
                Ok(v) => variants.push(v),
                Err(e) => return fail(2, format!("--variants: {e}")),
            }
        }
    }
    let opts = sphlab::study::StudyOptions { experiments, sizes, steps: a.steps, variants, out: a.out };
    match sphlab::study::run_study(&opts) {
        Ok(r) => {
            eprintln!("{} records; {}", r.len(), opts.out.join("summary.md").display());
            ExitCode::SUCCESS
        }
        Err(e) if e.starts_with("--") => fail(2, e),
        Err(e) => fail(1, e),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Run(a) => cmd_run(a),
        Cmd::Scene { cmd: SceneCmd::List } => {
            for n in builtin::BUILTIN {
                let s = builtin::builtin(n).expect("built-in");
                println!("{n:18} {}", s.description);
            }
            ExitCode::SUCCESS
        }
        Cmd::Scene { cmd: SceneCmd::Show { name } } => match builtin::builtin(&name) {
            Some(s) => {
                print!("{}", s.to_toml());
                ExitCode::SUCCESS
            }
            None => fail(2, format!("unknown scene `{name}` (built-in: {})", builtin::BUILTIN.join(", "))),
        },
        Cmd::Analytic { cmd } => cmd_analytic(cmd),
        Cmd::Variants => cmd_variants(),
        Cmd::Study(a) => cmd_study(a),
        Cmd::Verify(a) => cmd_verify(a),
        Cmd::Validate(a) => cmd_validate(a),
    }
}
