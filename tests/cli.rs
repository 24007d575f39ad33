//! The `sphlab` command line as a user meets it: every kind of bad input exits 2 with a message
//! naming what is wrong (never a panic), a blow-up exits 3 naming the step and particle and keeps
//! the outputs written so far, and a good run writes every promised file.

use std::path::Path;
use std::process::{Command, Output};

fn sphlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sphlab")).args(args).output().expect("the binary runs")
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
    assert_input_error(&["run", "oscillating-drop", "--set", "phases.0.rho0=-1", "--out", out], "phases[0].rho0");
    assert_input_error(&["run", "oscillating-drop", "--set", "fill=\"oil\"", "--out", out], "fill");
    assert_input_error(&["run", "oscillating-drop", "--set", "domain.left=\"periodic\"", "--out", out], "periodic");
    assert_input_error(&["run", "oscillating-drop", "--search", "octree", "--out", out], "--search");
    assert_input_error(&["run", "oscillating-drop", "--precision", "f16", "--out", out], "--precision");
    assert_input_error(&["run", "oscillating-drop", "--backend", "tpu", "--out", out], "--backend");
    assert_input_error(&["run", "oscillating-drop", "--t-end=-1", "--out", out], "--t-end");
    assert_input_error(&["scene", "show", "nope"], "unknown scene");
    assert_input_error(&["analytic", "spread", "--re=-3", "--we", "6", "--theta-deg", "90"], "Re");
    // The single-field colour gradient is CPU only: the GPU backend refuses it (no adapter needed),
    // and it needs contact.mode = "none".
    let single = ["--set", "surface_tension.colour_gradient=\"single-field\""];
    let gpu = [&["run", "oscillating-drop", "--backend", "gpu", "--out", out][..], &single[..]].concat();
    assert_input_error(&gpu, "colour_gradient");
    let mode_b = [&["run", "sessile-90", "--out", out][..], &single[..]].concat();
    assert_input_error(&mode_b, "surface_tension.colour_gradient");
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
        "output.every=1",
        "--out",
        out.to_str().expect("utf8"),
        "--quiet",
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "expected exit 3; stderr: {e}");
    assert!(e.contains("step") && e.contains("particle"), "message names step and particle: {e}");
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
    ] {
        assert!(header.split(',').any(|c| c == col), "series.csv has column {col}: {header}");
    }
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
    for s in ["contact_line", "wall_typing", "colour_gradient", "normal_correction", "surface_stress"] {
        assert!(stages.contains(&s), "Mode B runs {s}: {stages:?}");
    }
    assert!(summary["git_commit"].is_string() && summary["wall_particles"].as_u64().unwrap_or(0) > 0);
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
    assert_eq!(
        stages,
        ["neighbour_search", "number_density", "equation_of_state", "acceleration"],
        "a single-phase scene never pays for surface tension"
    );
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
