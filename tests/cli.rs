//! The `sphlab` command line as a user meets it: every kind of bad input exits 2 with a message
//! naming what is wrong (never a panic), before anything big is allocated and before any output
//! directory is created; a blow-up exits 3 naming the step and particle and keeps the outputs
//! written so far; Ctrl-C exits 130 with a final snapshot; a good run writes every promised file
//! with the provenance envelope. `robust_*` tests run the child under an address-space limit.

use std::path::Path;
use std::process::{Command, Output};

fn sphlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sphlab")).args(args).output().expect("the binary runs")
}

/// Address-space limit of children run by [`sphlab_limited`]: the binary, its threads' stacks
/// and malloc arenas need well under 1 GiB; a scene that slipped past the resource plan and
/// allocated gigabytes (the old failure) dies here instead of exiting 2.
const CHILD_AS_LIMIT: u64 = 1536 << 20;

/// `sphlab ARGS` under `prlimit --as` (plain when prlimit is missing).
fn sphlab_limited(args: &[&str]) -> Output {
    if Path::new("/usr/bin/prlimit").exists() {
        Command::new("/usr/bin/prlimit")
            .arg(format!("--as={CHILD_AS_LIMIT}"))
            .arg(env!("CARGO_BIN_EXE_sphlab"))
            .args(args)
            .output()
            .expect("prlimit runs")
    } else {
        sphlab(args)
    }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_input_error(args: &[&str], needle: &str) {
    let o = sphlab(args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: expected exit 2, got {:?}; stderr: {e}", o.status.code());
    assert!(e.contains(needle), "{args:?}: message should name `{needle}`; stderr: {e}");
    assert!(!e.contains("panicked"), "{args:?}: must not panic; stderr: {e}");
}

#[test]
fn bad_inputs_exit_2_with_a_message() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("o");
    let out = out.to_str().expect("utf8");
    assert_input_error(&["run", "no-such-scene", "--out", out], "unknown scene `no-such-scene`");
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "name = \"x\"\n[domain\nnx = 3\n").expect("write");
    assert_input_error(&["run", bad.to_str().expect("utf8"), "--out", out], "bad.toml");
    assert_input_error(&["run", "oscillating-drop", "--set", "drop.velocity_amplitude=0", "--out", out], "drop");
    assert_input_error(&["run", "oscillating-drop", "--set", "domain.nx=0", "--out", out], "domain.nx");
    assert_input_error(&["run", "oscillating-drop", "--set", "domain.x=[0.5, 0.0]", "--out", out], "domain.x");
    assert_input_error(&["run", "oscillating-drop", "--set", "phases=[]", "--out", out], "phases");
    assert_input_error(&["run", "oscillating-drop", "--set", "time.dt=-1", "--out", out], "time.dt");
    assert_input_error(&["run", "oscillating-drop", "--set", "domain.jitter=0.3", "--out", out], "domain.jitter");
    assert_input_error(&["run", "oscillating-drop", "--set", "phases.0.rho0=-1", "--out", out], "phases[0].rho0");
    assert_input_error(&["run", "oscillating-drop", "--set", "fill=\"oil\"", "--out", out], "fill");
    assert_input_error(&["run", "oscillating-drop", "--set", "domain.left=\"periodic\"", "--out", out], "periodic");
    assert_input_error(&["run", "oscillating-drop", "--search", "octree", "--out", out], "--search");
    assert_input_error(&["run", "oscillating-drop", "--precision", "f16", "--out", out], "--precision");
    assert_input_error(&["run", "oscillating-drop", "--backend", "tpu", "--out", out], "--backend");
    assert_input_error(&["run", "oscillating-drop", "--t-end=-1", "--out", out], "--t-end");
    assert_input_error(&["scene", "show", "nope"], "unknown scene");
    assert_input_error(&["scene", "relax-start", "180"], "(0, 180) degrees");
    assert_input_error(&["analytic", "spread", "--re=-3", "--we", "6", "--theta-deg", "90"], "Re");
    // The single-field colour gradient is CPU only: the GPU backend refuses it (no adapter needed),
    // and it needs contact.mode = "none".
    let single = ["--set", "surface_tension.colour_gradient=\"single-field\""];
    let gpu = [&["run", "oscillating-drop", "--backend", "gpu", "--out", out][..], &single[..]].concat();
    assert_input_error(&gpu, "colour_gradient");
    let mode_b = [&["run", "sessile-90", "--out", out][..], &single[..]].concat();
    assert_input_error(&mode_b, "surface_tension.colour_gradient");
    // So is the transport-velocity formulation.
    let tvf = ["--set", "time.background=\"transport\""];
    let gpu = [&["run", "oscillating-drop", "--backend", "gpu", "--out", out][..], &tvf[..]].concat();
    assert_input_error(&gpu, "time.background");
    // So is the tangential stress form.
    let tan = ["--set", "surface_tension.tensor=\"tangential\""];
    let gpu = [&["run", "oscillating-drop", "--backend", "gpu", "--out", out][..], &tan[..]].concat();
    assert_input_error(&gpu, "surface_tension.tensor");
    // So is Mode A's contact-line force.
    let line = ["--set", "contact.mode=\"a\"", "--set", "contact.line_force=true"];
    let gpu = [&["run", "relax-60", "--backend", "gpu", "--out", out][..], &line[..]].concat();
    assert_input_error(&gpu, "contact.line_force");
    // So are the wall's tensions at the contact line alone (σ_GS ≠ σ_LS).
    let line = ["--set", "contact.mode=\"a\"", "--set", "contact.wall_tension=\"line\""];
    let gpu = [&["run", "relax-60", "--backend", "gpu", "--out", out][..], &line[..]].concat();
    assert_input_error(&gpu, "contact.wall_tension");
    // The unbalanced Young force at a measured angle runs there, but spread over the interface
    // it does not (the WGSL force spreads by the kernel of the distance to the point).
    let unbalanced = [
        "--set",
        "contact.mode=\"a\"",
        "--set",
        "contact.wall_tension=\"unbalanced\"",
        "--set",
        "contact.line_force_spread=\"interface\"",
    ];
    let gpu = [&["run", "relax-60", "--backend", "gpu", "--out", out][..], &unbalanced[..]].concat();
    assert_input_error(&gpu, "contact.line_force_spread = \"interface\"");
    // And Mode A's liquid–gas interface left free at the wall.
    let free = ["--set", "contact.mode=\"a\"", "--set", "contact.liquid_gas_at_wall=\"free\""];
    let gpu = [&["run", "relax-60", "--backend", "gpu", "--out", out][..], &free[..]].concat();
    assert_input_error(&gpu, "contact.liquid_gas_at_wall");
    // clap's own errors (unknown flag) also exit 2.
    let o = sphlab(&["run", "oscillating-drop", "--no-such-flag"]);
    assert_eq!(o.status.code(), Some(2), "unknown flag exits 2");
}

#[test]
fn blow_up_exits_3_naming_step_and_particle_and_keeps_outputs() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("blow");
    // dt 300× the CFL limit: the run must blow up within a few steps.
    let o = sphlab(&[
        "run",
        "oscillating-drop",
        "--set",
        "relax.t=0",
        "--set",
        "time.dt=0.03",
        "--set",
        "time.dt_policy=warn",
        "--set",
        "output.every=1",
        "--out",
        out.to_str().expect("utf8"),
        "--quiet",
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "expected exit 3; stderr: {e}");
    assert!(e.contains("step") && e.contains("particle"), "message names step and particle: {e}");
    assert!(e.contains("CFL number") && e.contains("viscous number"), "message quotes the numbers reached: {e}");
    assert!(e.lines().all(|l| l.len() < 400), "a short position, not hundreds of digits: {e}");
    let series = std::fs::read_to_string(out.join("series.csv")).expect("series.csv kept");
    assert!(series.lines().count() >= 2, "header + at least the t = 0 row: {series}");
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("summary kept");
    assert!(summary.contains("blow-up"), "summary records the blow-up: {summary}");
}

#[test]
fn a_run_writes_series_snapshots_vtk_and_summary() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("run");
    let o = sphlab(&[
        "run",
        "sessile-90",
        "--set",
        "domain.nx=26",
        "--set",
        "output.every=5",
        "--steps",
        "20",
        "--every",
        "2",
        "--vtk",
        "--out",
        out.to_str().expect("utf8"),
        "--quiet",
    ]);
    assert!(o.status.success(), "run succeeds: {}", stderr(&o));
    let series = std::fs::read_to_string(out.join("series.csv")).expect("series");
    let header = series.lines().next().expect("header");
    for col in [
        "t",
        "step",
        "dt",
        "kinetic_energy",
        "centroid_x",
        "mass_phase0",
        "max_density_error",
        "theta_two_point",
        "theta_circle_fit",
        "theta_area",
        "spread_factor",
        "max_density_error_x",
        "max_speed_y",
    ] {
        assert!(header.split(',').any(|c| c == col), "series.csv has column {col}: {header}");
    }
    the_last_row_places_its_maxima_on_the_snapshots_particles(&series, &out.join("particles_00000020.csv"));
    assert_eq!(series.lines().count(), 1 + 5, "t = 0 plus one row every 5 of 20 steps");
    assert!(Path::new(&out.join("particles_00000020.csv")).exists(), "final snapshot");
    assert!(Path::new(&out.join("particles_00000020.vtu")).exists(), "final VTK");
    let pvd = std::fs::read_to_string(out.join("particles.pvd")).expect("pvd");
    assert!(pvd.contains("particles_00000020.vtu"), "pvd lists the final file");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
    assert_eq!(summary["status"], "ok");
    let stages: Vec<&str> =
        summary["active_stages"].as_array().expect("list").iter().filter_map(|v| v.as_str()).collect();
    use sphlab::stage::Stage;
    for s in
        [Stage::ContactLine, Stage::WallTyping, Stage::ColourGradient, Stage::NormalCorrection, Stage::SurfaceStress]
    {
        assert!(stages.contains(&s.name()), "Mode B runs {s}: {stages:?}");
    }
    assert!(summary["wall_particles"].as_u64().unwrap_or(0) > 0);
    let prov = &summary["provenance"];
    assert_eq!(prov["commit"], sphlab::provenance::commit_label().as_str());
    assert!(prov["schema_version"].as_u64() == Some(1) && prov["host"]["threads"].as_u64().unwrap_or(0) >= 1);
    assert_eq!(prov["units"]["t"], "T", "units of every series column");
    assert!(summary["plan"]["n_total"].as_f64().unwrap_or(0.0) > 0.0, "the resource plan is recorded");
    // The most neighbours one particle had: at least the start's largest list (the CPU's own
    // lists of the same layout), within the 64 a GPU list holds on this lattice.
    let scene = sphlab::scene::overrides::apply_overrides(
        &sphlab::scene::builtin::builtin("sessile-90").expect("builtin"),
        &["domain.nx=26".to_string()],
    )
    .expect("override");
    let layout = sphlab::scene::build::build_layout(&scene).expect("layout");
    let mut cpu = sphlab::cpu::CpuSolver::<f64>::new(
        &scene,
        &layout,
        sphlab::exec::Exec::Serial,
        sphlab::neighbours::SearchKind::Cells,
    );
    cpu.evaluate().expect("evaluation");
    let (start, peak) = (cpu.nbrs.max_count() as u64, summary["peak_neighbours"].as_u64().expect("CPU records it"));
    assert!(start > 20 && peak >= start && peak <= 64, "peak {peak}, start {start}");
}

/// The last series row's `max_density_error` and `max_speed` sit at the positions it names: the
/// fluid particle of the final snapshot (same step) with that |ρ − 1| (ρ0 = 1 in both phases of
/// sessile-90) and that speed.
fn the_last_row_places_its_maxima_on_the_snapshots_particles(series: &str, snapshot: &Path) {
    let mut lines = series.lines();
    let head: Vec<&str> = lines.next().expect("header").split(',').collect();
    let last: Vec<&str> = lines.last().expect("a row").split(',').collect();
    let col = |name: &str| -> f64 {
        let k = head.iter().position(|c| *c == name).unwrap_or_else(|| panic!("column {name}"));
        last[k].parse().unwrap_or_else(|_| panic!("{name} = {:?}", last[k]))
    };
    let snap = std::fs::read_to_string(snapshot).expect("final snapshot");
    let mut rows = snap.lines();
    let sh: Vec<&str> = rows.next().expect("header").split(',').collect();
    let k = |name: &str| sh.iter().position(|c| *c == name).unwrap_or_else(|| panic!("snapshot column {name}"));
    let (kx, ky, kvx, kvy, kr, kp) = (k("x"), k("y"), k("vx"), k("vy"), k("rho"), k("phase"));
    let fluid: Vec<Vec<f64>> = rows
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect::<Vec<f64>>())
        .filter(|r| r[kp] >= 0.0)
        .collect();
    let at = |x: f64, y: f64| {
        fluid.iter().find(|r| r[kx] == x && r[ky] == y).unwrap_or_else(|| panic!("a fluid particle at ({x}, {y})"))
    };
    let worst = fluid.iter().map(|r| (r[kr] - 1.0).abs()).fold(0.0, f64::max);
    let p = at(col("max_density_error_x"), col("max_density_error_y"));
    assert!((p[kr] - 1.0).abs() == worst && worst == col("max_density_error") && worst > 0.0, "{p:?} {worst}");
    let fastest = fluid.iter().map(|r| r[kvx].hypot(r[kvy])).fold(0.0, f64::max);
    let q = at(col("max_speed_x"), col("max_speed_y"));
    assert!(q[kvx].hypot(q[kvy]) == fastest && fastest == col("max_speed") && fastest > 0.0, "{q:?} {fastest}");
}

#[test]
fn single_phase_scene_runs_no_surface_tension_stages() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("poi");
    let o = sphlab(&["run", "poiseuille", "--steps", "3", "--out", out.to_str().expect("utf8"), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
    let stages: Vec<&str> =
        summary["active_stages"].as_array().expect("list").iter().filter_map(|v| v.as_str()).collect();
    use sphlab::stage::Stage;
    let always = [Stage::NeighbourSearch, Stage::NumberDensity, Stage::EquationOfState, Stage::Acceleration];
    assert_eq!(stages, always.map(Stage::name), "a single-phase scene never pays for surface tension");
}

#[test]
fn scene_relax_start_prints_the_overrides_of_validates_below_60_variants() {
    // examples/analysis/relax_start_angle.sh takes its start from here: the same cap as relax-60's variants.
    for theta in [45.0, 60.0, 120.0, 90.0] {
        let o = sphlab(&["scene", "relax-start", &theta.to_string()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let lines: Vec<String> = String::from_utf8(o.stdout).expect("utf8").lines().map(String::from).collect();
        assert_eq!(lines, sphlab::validate::relax_start_sets(theta), "θ0 = {theta}");
        assert_eq!(lines.is_empty(), theta == 90.0, "only 90° keeps the scene's half-disc: {lines:?}");
    }
}

#[test]
fn forces_reports_a_runs_force_balance_and_refuses_what_is_not_a_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("run");
    let out_s = out.to_str().expect("utf8");
    let o = sphlab(&[
        "run",
        "relax-60",
        "--threads",
        "1",
        "--set",
        "domain.nx=21",
        "--set",
        "contact.mode=a",
        "--steps",
        "40",
        "--every",
        "20",
        "--out",
        out_s,
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = dir.path().join("split.csv");
    let o = sphlab(&["forces", out_s, "--step", "40", "--csv", csv.to_str().expect("utf8")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let md = String::from_utf8(o.stdout).expect("utf8");
    for needle in [
        "step 40",
        "Mode A, σ_LG = 1, σ_LS = 0.5, σ_GS = 1",
        "| both | **all** |",
        "## x by row",
        "| liquid side |",
        "half of it +0.2500",
    ] {
        assert!(md.contains(needle), "no `{needle}` in:\n{md}");
    }
    let text = std::fs::read_to_string(&csv).expect("the per-particle CSV");
    assert_eq!(text.lines().next().map(|h| h.split(',').count()), Some(4 + 18), "header: {:?}", text.lines().next());
    assert_eq!(text.lines().count(), 1 + 21 * 21, "a header and one row per fluid particle (liquid and gas)");
    // The mean over the last two snapshots; its totals are the means of the two single ones.
    let o = sphlab(&["forces", out_s, "--last", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mean = String::from_utf8(o.stdout).expect("utf8");
    assert!(mean.contains("mean over the 2 snapshots from step 20 to step 40"), "{mean}");
    let total = |md: &str| -> f64 {
        let line = md.lines().find(|l| l.starts_with("| both | **all** |")).expect("the window's total row");
        line.split('|').nth(6).expect("sum column").trim().trim_matches('*').parse().expect("a number")
    };
    let at20 = String::from_utf8(sphlab(&["forces", out_s, "--step", "20"]).stdout).expect("utf8");
    assert!(
        (total(&mean) - 0.5 * (total(&md) + total(&at20))).abs() < 2e-4,
        "{} vs {} and {}",
        total(&mean),
        total(&md),
        total(&at20)
    );
    // Three cuts per side: six rows and each side's mean and range; the default's two cuts are
    // the profile's middle ones (half-way to the contact point).
    let o = sphlab(&["forces", out_s, "--step", "40", "--cuts-per-side", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let prof = String::from_utf8(o.stdout).expect("utf8");
    let cut_rows = |md: &str| {
        md.lines().filter(|l| l.starts_with("| liquid side | 0.") || l.starts_with("| gas side | 0.")).count()
    };
    assert_eq!((cut_rows(&md), cut_rows(&prof)), (2, 6), "{prof}");
    for needle in ["| liquid side | 3 | ", "| gas side | 3 | ", "Gas side − liquid side (means over the cuts)"] {
        assert!(prof.contains(needle), "no `{needle}` in:\n{prof}");
    }
    let row =
        |md: &str, k: usize| md.lines().filter(|l| l.starts_with("| liquid side | 0.")).nth(k).map(str::to_string);
    assert_eq!(row(&md, 0), row(&prof, 1), "the half-way cut under the liquid");
    // Inputs that are not a run, a missing step, a bad window: exit 2 naming what is wrong.
    assert_input_error(&["forces", dir.path().to_str().expect("utf8")], "summary.json");
    assert_input_error(&["forces", out_s, "--step", "7"], "--step 7: no such snapshot");
    assert_input_error(&["forces", out_s, "--half-width", "0"], "--half-width 0");
    assert_input_error(&["forces", out_s, "--last", "4"], "--last 4");
    assert_input_error(&["forces", out_s, "--cuts-per-side", "0"], "--cuts-per-side 0");
}

#[test]
fn scene_show_round_trips_through_toml_and_runs() {
    let dir = tempfile::tempdir().expect("tempdir");
    for name in sphlab::scene::builtin::BUILTIN {
        let o = sphlab(&["scene", "show", name]);
        assert!(o.status.success(), "scene show {name}");
        let text = String::from_utf8(o.stdout).expect("utf8");
        let parsed = sphlab::scene::Scene::from_toml(&text).expect("shown TOML parses");
        assert_eq!(parsed, sphlab::scene::builtin::builtin(name).expect("builtin"), "{name} round-trips");
        let file = dir.path().join(format!("{name}.toml"));
        std::fs::write(&file, &text).expect("write");
        let out = dir.path().join(format!("{name}-out"));
        let o = sphlab(&[
            "run",
            file.to_str().expect("utf8"),
            "--steps",
            "1",
            "--out",
            out.to_str().expect("utf8"),
            "--quiet",
            "--set",
            "domain.nx=24",
        ]);
        assert!(o.status.success(), "{name} runs from its TOML: {}", stderr(&o));
    }
}

#[test]
fn analytic_table1_prints_the_whole_table() {
    let o = sphlab(&["analytic", "table1"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).expect("utf8");
    assert!(text.lines().count() >= 33, "33 rows: {text}");
    let o = sphlab(&["analytic", "spread", "--re", "440", "--we", "6.86", "--theta-deg", "90", "--json"]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let axi = v["axisym"].as_f64().expect("axisym");
    assert!((axi - 2.092).abs() < 2e-3, "axisymmetric D_max/D0 at 90° = {axi}");
}

fn assert_input_error_limited(args: &[&str], needle: &str) {
    let o = sphlab_limited(args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: expected exit 2, got {:?}; stderr: {e}", o.status.code());
    assert!(e.contains(needle), "{args:?}: message should name `{needle}`; stderr: {e}");
}

#[test]
fn robust_huge_scenes_are_refused_by_the_plan_before_allocation() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("o");
    let out = out.to_str().expect("utf8");
    // Each of these used to allocate until it died (4–5 GB, SIGABRT) or panicked.
    for (set, needle) in [
        ("domain.nx=5000", "resource plan"),
        ("domain.nx=20000", "resource plan"),
        ("domain.y=[0, 1e300]", "domain.y"),
        ("domain.y=[0, 1e5]", "resource plan"),
        ("domain.x=[0, 1e-300]", "domain.x"),
        ("kernel.h_ratio=0.001", "kernel.h_ratio"),
        ("kernel.h_ratio=1e-12", "kernel.h_ratio"),
    ] {
        assert_input_error_limited(&["run", "oscillating-drop", "--set", set, "--out", out], needle);
    }
    // The plan's numbers are in the message, and the limits are settable.
    let o = sphlab_limited(&["run", "sessile-90", "--max-particles", "500", "--out", out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--max-particles") && stderr(&o).contains("wall"), "{}", stderr(&o));
    let o = sphlab_limited(&["run", "sessile-90", "--max-memory", "2M", "--out", out]);
    assert!(o.status.code() == Some(2) && stderr(&o).contains("--max-memory"), "{}", stderr(&o));
    assert_input_error_limited(&["run", "sessile-90", "--max-memory", "lots", "--out", out], "--max-memory");
    assert_input_error_limited(&["study", "--sizes", "100000", "--out", out], "--sizes 100000");
    assert_input_error_limited(&["study", "--sizes", "30,abc", "--out", out], "--sizes");
    assert!(!Path::new(out).exists(), "no output directory for refused input");
}

#[test]
fn robust_out_problems_and_options_exit_2_before_creating_anything() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("file");
    std::fs::write(&file, "x").expect("write");
    let long = dir.path().join("n".repeat(300));
    let fresh = dir.path().join("fresh");
    let (file, long, fresh) =
        (file.to_str().expect("utf8"), long.to_str().expect("utf8"), fresh.to_str().expect("utf8"));
    for out in [file, "/dev/null", "/proc/sphlab-test", long] {
        assert_input_error(&["run", "poiseuille", "--steps", "1", "--out", out], "--out");
        assert_input_error(&["study", "--out", out], "--out");
        assert_input_error(&["validate", "oscillation", "--quick", "--out", out], "--out");
        assert_input_error(&["verify", "--out", out], "--out");
    }
    // Variant ids and options that do not fit the backend, in every command.
    assert_input_error(&["validate", "oscillation", "--variant", "bogus", "--backend", "gpu", "--out", fresh], "bogus");
    assert_input_error(
        &["validate", "oscillation", "--variant", "cells.thread.recomputed.f32", "--out", fresh],
        "--variant",
    );
    assert_input_error(&["run", "--backend", "gpu", "--variant", "bogus", "--out", fresh], "--variant");
    assert_input_error(&["run", "--variant", "cells.thread.recomputed.f32", "--out", fresh], "--backend gpu");
    assert_input_error(&["run", "--backend", "gpu", "--precision", "f64", "--out", fresh], "--precision");
    assert_input_error(&["run", "--backend", "gpu", "--search", "tracking", "--out", fresh], "--search");
    assert_input_error(&["validate", "oscillation", "--backend", "tpu", "--out", fresh], "--backend");
    assert_input_error(&["verify", "--variants", "nope", "--out", fresh], "--variants");
    assert_input_error(&["study", "--variants", "nope", "--out", fresh], "--variants");
    assert!(!Path::new(fresh).exists(), "nothing was created for bad input");
    // Typed options list their choices and suggest the near miss.
    let o = sphlab(&["validate", "oscilation"]);
    assert!(o.status.code() == Some(2) && stderr(&o).contains("oscillation"), "{}", stderr(&o));
    let o = sphlab(&["study", "--experiments", "e5"]);
    assert!(o.status.code() == Some(2) && stderr(&o).contains("e1"), "{}", stderr(&o));
    let o = sphlab(&["run", "--search", "cell"]);
    assert!(o.status.code() == Some(2) && stderr(&o).contains("cells"), "{}", stderr(&o));
    assert_input_error(&["--threads", "0", "run", "--out", fresh], "--threads");
}

#[test]
fn robust_fields_are_checked_at_load_naming_the_field_and_range() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("o");
    let out = out.to_str().expect("utf8");
    // Each used to be accepted and fail later as NaN (exit 3) or name a consequence.
    for (set, needle) in [
        ("phases.0.mu=1e300", "phases[0].mu"),
        ("phases.0.rho0=1e-300", "phases[0].rho0"),
        ("phases.0.gamma=1e300", "phases[0].gamma"),
        ("phases.0.c0=nan", "phases[0].c0"),
        ("phases.0.p_b=-1", "phases[0].p_b"),
        ("shapes.0.velocity=[inf, 0]", "shapes[0].velocity"),
        ("shapes.0.centre=[50, 50]", "shapes[0].centre"),
        ("shapes.0.radius=-0.0", "shapes[0].radius"),
        ("gravity=[0, -1e300]", "gravity"),
        ("surface_tension.sigma=inf", "surface_tension.sigma"),
        ("contact.band=0", "contact.band"),
        ("walls.beta_max=nan", "walls.beta_max"),
        ("time.dt=5", "time.dt"),
        ("time.cfl=nan", "time.cfl"),
        ("kernel.h_ratio=20", "kernel.h_ratio"),
        ("domain.nx=2", "domain.nx"),
    ] {
        let o = sphlab_limited(&["run", "sessile-90", "--set", set, "--out", out]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{set}: {e}");
        assert!(e.contains(&format!("`{needle}`")), "{set}: the message names `{needle}`: {e}");
        assert!(e.contains('[') || e.contains('('), "{set}: the message gives the accepted range: {e}");
        assert!(e.len() < 600, "{set}: short message: {e}");
    }
    // The same in a scene file: γ beyond f64 (TOML reads it as out of range or ∞).
    let text = sphlab::scene::builtin::builtin("sessile-90").expect("built-in").to_toml();
    let gamma = text.lines().find(|l| l.starts_with("gamma")).expect("a gamma line").to_string();
    let file = dir.path().join("g.toml");
    std::fs::write(&file, text.replacen(&gamma, "gamma = 1.8e308", 1)).expect("write");
    let o = sphlab_limited(&["run", file.to_str().expect("utf8"), "--out", out]);
    assert!(o.status.code() == Some(2) && stderr(&o).contains("gamma"), "{}", stderr(&o));
}

#[test]
fn every_counts_steps_exactly_and_the_vtk_has_id_mass_h() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("run");
    let o = sphlab(&[
        "run",
        "poiseuille",
        "--set",
        "output.every=3",
        "--steps",
        "20",
        "--every",
        "5",
        "--vtk",
        "--out",
        out.to_str().expect("utf8"),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut snaps: Vec<u64> = std::fs::read_dir(&out)
        .expect("dir")
        .filter_map(|e| e.ok()?.file_name().to_str()?.strip_prefix("particles_")?.strip_suffix(".csv")?.parse().ok())
        .collect();
    snaps.sort();
    assert_eq!(snaps, [0, 5, 10, 15, 20], "a snapshot at every 5th step, first and last");
    let series = std::fs::read_to_string(out.join("series.csv")).expect("series");
    let steps: Vec<u64> = series.lines().skip(1).map(|l| l.split(',').nth(1).unwrap().parse().unwrap()).collect();
    assert_eq!(steps, [0, 3, 6, 9, 12, 15, 18, 20], "a row every output.every steps and the last");
    let vtu = std::fs::read_to_string(out.join("particles_00000020.vtu")).expect("vtu");
    for name in ["\"id\"", "\"mass\"", "\"h\""] {
        assert!(vtu.contains(&format!("Name={name}")), "VTK point data {name}");
    }
}

#[test]
fn ctrl_c_exits_130_with_a_final_snapshot_and_interrupted_status() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("int");
    let child = Command::new(env!("CARGO_BIN_EXE_sphlab"))
        .args(["run", "poiseuille", "--steps", "10000000", "--every", "0", "--quiet", "--out"])
        .arg(&out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    // Wait until it steps (series.csv has its t = 0 row), then interrupt.
    let t0 = std::time::Instant::now();
    while !std::fs::read_to_string(out.join("series.csv")).is_ok_and(|s| s.lines().count() >= 2) {
        assert!(t0.elapsed().as_secs() < 300, "hang guard: the run never started");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    let ok = Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
    assert!(ok.success());
    let o = child.wait_with_output().expect("wait");
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
    assert_eq!(summary["status"], "interrupted");
    let steps = summary["steps"].as_u64().expect("steps");
    assert!(steps > 0 && steps < 10_000_000, "the step reached: {steps}");
    assert!(out.join(format!("particles_{steps:08}.csv")).exists(), "final snapshot at step {steps}");
    let series = std::fs::read_to_string(out.join("series.csv")).expect("series");
    assert!(series.lines().last().unwrap().split(',').nth(1) == Some(&steps.to_string()), "last row");
}

#[test]
fn provenance_is_sphlabs_own_commit_whatever_the_directory() {
    let o = sphlab(&["--version"]);
    let v = String::from_utf8_lossy(&o.stdout);
    assert!(v.contains(sphlab::provenance::BUILD_COMMIT), "--version shows the commit: {v}");
    // An unrelated repository as the working directory.
    let repo = tempfile::tempdir().expect("tempdir");
    let git = |args: &[&str]| {
        Command::new("git")
            .args(["-c", "user.name=t", "-c", "user.email=t@t", "-c", "commit.gpgsign=false"])
            .args(args)
            .current_dir(repo.path())
            .output()
    };
    let has_git = git(&["init", "-q"]).is_ok_and(|o| o.status.success());
    if has_git {
        std::fs::write(repo.path().join("f"), "x").expect("write");
        git(&["add", "f"]).expect("git add");
        git(&["commit", "-q", "-m", "other"]).expect("git commit");
    }
    let o = Command::new(env!("CARGO_BIN_EXE_sphlab"))
        .args(["run", "poiseuille", "--steps", "1", "--quiet", "--out", "o"])
        .current_dir(repo.path())
        .env_remove("SPHLAB_GIT_COMMIT")
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(repo.path().join("o/summary.json")).expect("summary"))
            .expect("json");
    assert_eq!(summary["provenance"]["commit"], sphlab::provenance::commit_label().as_str());
    if has_git {
        let other = git(&["rev-parse", "--short=10", "HEAD"]).expect("rev-parse");
        let other = String::from_utf8_lossy(&other.stdout).trim().to_string();
        assert_ne!(summary["provenance"]["commit"], other.as_str(), "not the surrounding repository's commit");
    }
}

#[test]
fn json_outputs_carry_the_envelope() {
    let o = sphlab(&["info", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("info --json");
    assert!(v["adapters"].is_array() && v["provenance"]["host"]["cpus"].as_u64().unwrap_or(0) >= 1);
    let o = sphlab(&["scene", "list", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("scene list --json");
    assert_eq!(v["scenes"].as_array().map(Vec::len), Some(sphlab::scene::builtin::BUILTIN.len()));
    let o = sphlab(&["variants", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("variants --json");
    assert!(v["variants"].as_array().is_some_and(|a| !a.is_empty()) && v["provenance"]["commit"].is_string());
    let o = sphlab(&["analytic", "table1", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("table1 --json");
    assert!(v["rows"].is_array() && v["provenance"]["units"].is_object());
}

mod fuzz {
    //! Random scene files and flag sets thrown at `sphlab run` under a memory limit: the exit
    //! code is 0, 2 or 3 only; 2 and 3 come with a message; a run that got as far as writing
    //! `summary.json` / `series.csv` leaves them complete and parseable; and nothing dies of
    //! allocation (the child's address space is capped at [`super::CHILD_AS_LIMIT`], with
    //! `--max-memory 256M`, so a scene the plan admits must really fit).
    //!
    //! 48 cases: each is one child process (`--steps 2`, lattices of 12–27 across): refusals
    //! take milliseconds, runs 0.1–0.3 s, about 2 s in all (24 cases measured 1.0 s); the
    //! mutation table covers every class of the issue (non-finite, huge, tiny, negative, wrong
    //! type, swapped bounds, truncated file) and proptest's seed varies which combinations run.

    use super::*;
    use proptest::prelude::*;

    const KEYS: &[&str] = &[
        "domain.nx",
        "domain.x",
        "domain.y",
        "domain.left",
        "kernel.h_ratio",
        "kernel.kind",
        "phases.0.rho0",
        "phases.0.mu",
        "phases.0.c0",
        "phases.0.gamma",
        "phases.0.p_b",
        "time.dt",
        "time.cfl",
        "time.xsph",
        "shapes.0.radius",
        "shapes.0.velocity",
        "gravity",
        "surface_tension.sigma",
        "contact.theta_deg",
        "walls.beta_max",
        "output.every",
        "fill",
    ];
    const VALUES: &[&str] = &[
        "0",
        "-1",
        "-0.0",
        "1e300",
        "-1e300",
        "1e-300",
        "nan",
        "inf",
        "-inf",
        "2",
        "7",
        "0.5",
        "1.0",
        "3000",
        "\"x\"",
        "true",
        "[]",
        "[0, 1e300]",
        "[1, 0]",
        "[0, 1]",
        "[0.0, -9.8]",
        "\"periodic\"",
        "\"quintic\"",
    ];

    fn outcome_is_sound(o: &Output, out: &Path, what: &str) {
        let e = stderr(o);
        let code = o.status.code();
        assert!(matches!(code, Some(0 | 2 | 3)), "{what}: exit {code:?} (signal or unexpected code); stderr: {e}");
        if code != Some(0) {
            assert!(e.trim().len() > "error: ".len(), "{what}: exit {code:?} needs a message");
            assert!(!e.contains("panicked"), "{what}: panic: {e}");
        }
        if let Ok(text) = std::fs::read_to_string(out.join("summary.json")) {
            let v: serde_json::Value =
                serde_json::from_str(&text).unwrap_or_else(|err| panic!("{what}: summary.json ({err}): {text}"));
            let status = v["status"].as_str().unwrap_or("");
            assert!(status == "ok" || status.starts_with("blow-up"), "{what}: status {status}");
            assert_eq!(code == Some(0), status == "ok", "{what}: status {status} vs exit {code:?}");
        }
        if let Ok(text) = std::fs::read_to_string(out.join("series.csv")) {
            let mut r = csv::Reader::from_reader(text.as_bytes());
            let width = r.headers().expect("header").len();
            let mut rows = 0;
            for rec in r.records() {
                let rec = rec.unwrap_or_else(|err| panic!("{what}: series.csv row ({err}): {text}"));
                assert_eq!(rec.len(), width, "{what}: complete row");
                rows += 1;
            }
            assert!(rows >= 1, "{what}: at least the t = 0 row");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]
        #[test]
        fn random_scenes_and_flags_exit_0_2_or_3_within_the_plan(
            base in 0usize..sphlab::scene::builtin::BUILTIN.len(),
            nx in 12u32..28,
            sets in proptest::collection::vec((0usize..KEYS.len(), 0usize..VALUES.len()), 0..3),
            as_file in any::<bool>(),
            truncate in proptest::option::of(0.0f64..1.0),
            precision in 0usize..3,
            search in 0usize..4,
            every in 0u64..4,
            vtk in any::<bool>(),
        ) {
            let name = sphlab::scene::builtin::BUILTIN[base];
            let dir = tempfile::tempdir().expect("tempdir");
            let out = dir.path().join("out");
            let mut args: Vec<String> = vec!["run".into()];
            if as_file {
                // A scene file, perhaps cut short at a random byte (malformed TOML).
                let mut text = sphlab::scene::builtin::builtin(name).expect("built-in").to_toml();
                if let Some(f) = truncate {
                    let mut cut = (text.len() as f64 * f) as usize;
                    while !text.is_char_boundary(cut) {
                        cut -= 1;
                    }
                    text.truncate(cut);
                }
                let file = dir.path().join("scene.toml");
                std::fs::write(&file, text).expect("write");
                args.push(file.to_str().expect("utf8").into());
            } else {
                args.push(name.into());
            }
            args.extend(["--set".into(), format!("domain.nx={nx}"), "--set".into(), "relax.t=0".into()]);
            for (k, v) in &sets {
                args.extend(["--set".into(), format!("{}={}", KEYS[*k], VALUES[*v])]);
            }
            if let Some(p) = ["f64", "f32"].get(precision) {
                args.extend(["--precision".into(), p.to_string()]);
            }
            if let Some(s) = ["direct", "cells", "tracking"].get(search) {
                args.extend(["--search".into(), s.to_string()]);
            }
            args.extend(["--every".into(), every.to_string(), "--steps".into(), "2".into(), "--quiet".into()]);
            args.extend(["--max-memory".into(), "256M".into(), "--out".into(), out.to_str().expect("utf8").into()]);
            if vtk {
                args.push("--vtk".into());
            }
            let refs: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = sphlab_limited(&refs);
            outcome_is_sound(&o, &out, &format!("{refs:?}"));
        }
    }
}
