//! `validate --reuse` finds a finished run of exactly the scene asked for: a run written before
//! a scene field existed is reused when the field's default is what is asked for, and never when
//! a parameter differs.

use sphlab::scene::builtin::oscillating_drop;
use sphlab::validate::RunRecord;

fn write_run(dir: &std::path::Path, params: serde_json::Value) {
    let summary = serde_json::json!({
        "scene": "oscillating-drop",
        "parameters": params,
        "options": { "backend": "cpu1.cells.f64", "t_end": 0.1, "steps": null },
        "status": "ok",
        "steps": 10,
    });
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
}

#[test]
fn a_run_from_before_a_field_existed_is_reused_at_its_default() {
    let scene = oscillating_drop();
    let tmp = tempfile::tempdir().unwrap();
    let run = tmp.path().join("old");
    let mut params = serde_json::to_value(&scene).unwrap();
    assert_eq!(params["contact"]["line_force"], false, "the field this test removes");
    params["contact"].as_object_mut().unwrap().remove("line_force");
    write_run(&run, params.clone());
    assert!(RunRecord::reuse(&run, &scene, Some(0.1), "cmd").is_some(), "missing field = its default");
    // Asked with the field away from its default: not the run that was made.
    let mut forced = scene.clone();
    forced.contact.line_force = true;
    assert!(RunRecord::reuse(&run, &forced, Some(0.1), "cmd").is_none());
    // Another end time, or a parameter changed, is never reused.
    assert!(RunRecord::reuse(&run, &scene, Some(0.2), "cmd").is_none());
    let mut changed = params;
    changed["phases"][0]["rho0"] = serde_json::json!(2.0);
    write_run(&run, changed);
    assert!(RunRecord::reuse(&run, &scene, Some(0.1), "cmd").is_none());
}
