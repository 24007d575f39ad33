//! Tests of `sphlab::output` (snapshot CSV/VTU/PVD, series CSV, JSON summary, timestamps,
//! progress) and `sphlab::plot` (SVG plots).

use std::fs;
use std::path::Path;

use serde::Serialize;
use sphlab::output::{
    self, iso8601_from_unix, now_utc_iso8601, write_json, write_particles_csv, write_vtu, OutputError, Progress,
    PvdWriter, SeriesWriter, Snapshot,
};
use sphlab::plot::{fmt_tick, line_plot_svg, scatter_labeled_svg, PlotSpec, RefLine, Series, Style};

fn snapshot(n: usize, step: u64) -> Snapshot {
    Snapshot {
        step,
        t: step as f64 / 1e4,
        pos: (0..n).map(|i| [i as f64 * 0.1, 0.5 - i as f64 * 0.01]).collect(),
        vel: (0..n).map(|i| [i as f64, -(i as f64)]).collect(),
        rho: (0..n).map(|i| 1000.0 + i as f64).collect(),
        p: (0..n).map(|i| 10.0 * i as f64).collect(),
        phase: (0..n).map(|i| if i % 4 == 3 { u32::MAX } else { (i % 2) as u32 }).collect(),
        grad_c: (0..n).map(|i| [0.5 * i as f64, 1.0]).collect(),
        mass: (0..n).map(|i| 0.01 * (1 + i % 3) as f64).collect(),
        h: 0.02,
    }
}

// ---------------------------------------------------------------------------------------------
// Particle CSV

#[test]
fn particles_csv_header_rows_and_walls() {
    let dir = tempfile::tempdir().unwrap();
    let snap = snapshot(7, 42);
    let path = write_particles_csv(dir.path(), &snap).unwrap();
    assert_eq!(path, dir.path().join("particles_00000042.csv"));
    let text = fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "id,x,y,vx,vy,rho,p,phase,gcx,gcy");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 7);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 10);
        assert_eq!(r[0].parse::<usize>().unwrap(), i);
        assert_eq!(r[1].parse::<f64>().unwrap(), snap.pos[i][0]);
        assert_eq!(r[5].parse::<f64>().unwrap(), snap.rho[i]);
        let want_phase = if i % 4 == 3 { -1 } else { (i % 2) as i64 };
        assert_eq!(r[7].parse::<i64>().unwrap(), want_phase);
        assert_eq!(r[8].parse::<f64>().unwrap(), snap.grad_c[i][0]);
    }
}

#[test]
fn particles_csv_empty_snapshot_has_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_particles_csv(dir.path().join("sub/dir"), &snapshot(0, 3)).unwrap();
    let text = fs::read_to_string(path).unwrap();
    assert_eq!(text.trim_end(), "id,x,y,vx,vy,rho,p,phase,gcx,gcy");
}

#[test]
fn mismatched_snapshot_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut snap = snapshot(5, 1);
    snap.rho.pop();
    let err = write_particles_csv(dir.path(), &snap).unwrap_err();
    assert!(matches!(err, OutputError::Data { .. }), "{err}");
    assert!(err.to_string().contains("particles_00000001.csv"), "{err}");
    assert!(write_vtu(dir.path(), &snap).is_err());
}

#[test]
fn io_error_names_the_path() {
    let dir = tempfile::tempdir().unwrap();
    // A file where a directory is expected.
    let blocker = dir.path().join("blocker");
    fs::write(&blocker, "x").unwrap();
    let err = write_particles_csv(blocker.join("out"), &snapshot(2, 0)).unwrap_err();
    assert!(err.to_string().contains("blocker"), "{err}");
    assert!(err.path().starts_with(&blocker));
}

// ---------------------------------------------------------------------------------------------
// VTU / PVD

/// Checks that start and end tags balance (a small well-formedness check, no XML crate).
fn assert_tags_balanced(xml: &str) {
    let mut stack: Vec<String> = Vec::new();
    let mut rest = xml;
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unclosed tag") + start;
        let tag = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') || tag.starts_with('!') {
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack.pop().unwrap_or_else(|| panic!("stray </{name}>"));
            assert_eq!(open, name.trim(), "mismatched end tag");
        } else if !tag.ends_with('/') {
            stack.push(tag.split_whitespace().next().unwrap().to_string());
        }
    }
    assert!(stack.is_empty(), "unclosed elements {stack:?}");
}

/// `(attributes, body)` of every `<DataArray ...>body</DataArray>` in `xml`.
fn data_arrays(xml: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = xml;
    while let Some(s) = rest.find("<DataArray") {
        let open_end = rest[s..].find('>').unwrap() + s;
        let attrs = rest[s + 10..open_end].to_string();
        let close = rest[open_end..].find("</DataArray>").unwrap() + open_end;
        out.push((attrs, rest[open_end + 1..close].to_string()));
        rest = &rest[close + 12..];
    }
    out
}

fn attr<'a>(attrs: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let s = attrs.find(&key)? + key.len();
    let e = attrs[s..].find('"')? + s;
    Some(&attrs[s..e])
}

#[test]
fn vtu_is_well_formed() {
    let dir = tempfile::tempdir().unwrap();
    let n = 23;
    let mut snap = snapshot(n, 1200);
    snap.p[3] = f64::NAN; // a blown-up value still writes
    let path = write_vtu(dir.path(), &snap).unwrap();
    assert_eq!(path, dir.path().join("particles_00001200.vtu"));
    let xml = fs::read_to_string(&path).unwrap();
    assert!(xml.starts_with("<?xml"));
    assert!(xml.contains("type=\"UnstructuredGrid\""));
    assert!(xml.contains(&format!("NumberOfPoints=\"{n}\"")));
    assert!(xml.contains(&format!("NumberOfCells=\"{n}\"")));
    assert_tags_balanced(&xml);

    let arrays = data_arrays(&xml);
    let mut names = Vec::new();
    for (attrs, body) in &arrays {
        let tokens: Vec<&str> = body.split_whitespace().collect();
        if let Some(tuples) = attr(attrs, "NumberOfTuples") {
            // field data (time, step)
            assert_eq!(tokens.len(), tuples.parse::<usize>().unwrap());
            continue;
        }
        let comps: usize = attr(attrs, "NumberOfComponents").map(|c| c.parse().unwrap()).unwrap_or(1);
        let name = attr(attrs, "Name").unwrap().to_string();
        assert_eq!(tokens.len(), n * comps, "array {name}");
        let ty = attr(attrs, "type").unwrap();
        if ty.starts_with("Float") {
            for t in &tokens {
                assert!(t.parse::<f64>().is_ok(), "{name}: {t}");
            }
        } else {
            for t in &tokens {
                assert!(t.parse::<i64>().is_ok(), "{name}: {t}");
            }
        }
        names.push((name, ty.to_string(), comps, tokens.iter().map(|t| t.to_string()).collect::<Vec<_>>()));
    }
    let find = |nm: &str| names.iter().find(|a| a.0 == nm).unwrap_or_else(|| panic!("no {nm}"));
    assert_eq!(find("velocity").2, 3);
    assert_eq!(find("grad_c").2, 3);
    assert_eq!(find("rho").2, 1);
    assert_eq!(find("p").2, 1);
    let phase = find("phase");
    assert_eq!(phase.1, "Int32");
    assert_eq!(phase.3[3], "-1");
    assert_eq!(phase.3[1], "1");
    let points = find("Points");
    assert_eq!(points.2, 3);
    for i in 0..n {
        assert_eq!(points.3[3 * i + 2].parse::<f64>().unwrap(), 0.0);
        assert_eq!(points.3[3 * i].parse::<f64>().unwrap(), snap.pos[i][0]);
    }
    assert!(find("p").3[3].parse::<f64>().unwrap().is_nan());
    assert!(find("types").3.iter().all(|t| t == "1"));
    assert_eq!(find("offsets").3.last().unwrap(), &n.to_string());
    // Particle id, mass and smoothing length.
    assert_eq!(find("id").3, (0..n).map(|i| i.to_string()).collect::<Vec<_>>());
    assert_eq!(find("mass").3[4].parse::<f64>().unwrap(), snap.mass[4]);
    assert!(find("h").3.iter().all(|t| t.parse::<f64>().unwrap() == 0.02));
}

/// Decodes standard base64 (the inverse of `output::base64_into`), for the test only.
fn base64_decode(text: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let bytes: Vec<u8> = text.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    let mut out = Vec::new();
    for q in bytes.chunks(4) {
        let pad = q.iter().filter(|&&c| c == b'=').count();
        let v = q.iter().take(4 - pad).enumerate().fold(0u32, |a, (k, &c)| a | (val(c) as u32) << (18 - 6 * k));
        out.extend_from_slice(&v.to_be_bytes()[1..4 - pad]);
    }
    out
}

#[test]
fn base64_matches_rfc4648_vectors() {
    for (raw, enc) in [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foobar", "Zm9vYmFy")] {
        let mut s = String::new();
        output::base64_into(&mut s, raw.as_bytes());
        assert_eq!(s, enc);
        assert_eq!(base64_decode(enc), raw.as_bytes());
    }
}

#[test]
fn binary_vtu_holds_the_same_values_as_ascii() {
    let n = 37;
    let snap = snapshot(n, 7);
    let ascii = data_arrays(&output::vtu_text(&snap, false));
    let binary = data_arrays(&output::vtu_text(&snap, true));
    assert_eq!(ascii.len(), binary.len());
    for ((aa, ab), (ba, bb)) in ascii.iter().zip(&binary) {
        let name = attr(aa, "Name").unwrap();
        if attr(aa, "NumberOfTuples").is_some() {
            continue; // field data stays ASCII
        }
        assert_eq!(attr(ba, "format"), Some("binary"), "{name}");
        let raw = base64_decode(bb);
        let len = u64::from_le_bytes(raw[..8].try_into().unwrap()) as usize;
        assert_eq!(len, raw.len() - 8, "{name}: UInt64 byte-count header");
        let tokens: Vec<&str> = ab.split_whitespace().collect();
        let ty = attr(aa, "type").unwrap();
        let width = match ty {
            "Float64" | "Int64" => 8,
            "Int32" => 4,
            "UInt8" => 1,
            t => panic!("type {t}"),
        };
        assert_eq!(len, tokens.len() * width, "{name}");
        for (k, t) in tokens.iter().enumerate() {
            let b = &raw[8 + k * width..8 + (k + 1) * width];
            match ty {
                "Float64" => {
                    let v = f64::from_le_bytes(b.try_into().unwrap());
                    let a: f64 = t.parse().unwrap();
                    assert!(v == a || (v.is_nan() && a.is_nan()), "{name}[{k}]: {v} vs {a}");
                }
                "Int64" => assert_eq!(i64::from_le_bytes(b.try_into().unwrap()).to_string(), *t, "{name}[{k}]"),
                "Int32" => assert_eq!(i32::from_le_bytes(b.try_into().unwrap()).to_string(), *t, "{name}[{k}]"),
                _ => assert_eq!(b[0].to_string(), *t, "{name}[{k}]"),
            }
        }
    }
    // Large snapshots go binary on their own.
    let dir = tempfile::tempdir().unwrap();
    let big = snapshot(output::VTK_BINARY_MIN, 1);
    let xml = fs::read_to_string(write_vtu(dir.path(), &big).unwrap()).unwrap();
    assert!(xml.contains("format=\"binary\"") && !xml.contains("format=\"ascii\">\n"));
}

#[test]
fn out_dir_problems_are_named_before_anything_is_created() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("f");
    fs::write(&file, "x").unwrap();
    let bad = [
        (file.clone(), "not a directory"),
        (file.join("sub"), "not a directory"),
        (Path::new("/dev/null").to_path_buf(), "not a directory"),
        (Path::new("/proc/sphlab-out").to_path_buf(), "/proc"),
        (dir.path().join("a".repeat(300)), "255"),
        (Path::new("").to_path_buf(), "empty"),
    ];
    for (p, needle) in bad {
        let e = output::check_out_dir(&p).expect_err(&format!("{} must be refused", p.display()));
        assert!(e.contains(needle), "{}: {e}", p.display());
    }
    assert!(output::check_out_dir(&dir.path().join("new/deeper")).is_ok());
    assert!(!dir.path().join("new").exists(), "checking creates nothing");
}

#[test]
fn vtu_without_grad_c_writes_zeros() {
    let dir = tempfile::tempdir().unwrap();
    let mut snap = snapshot(4, 0);
    snap.grad_c.clear();
    let xml = fs::read_to_string(write_vtu(dir.path(), &snap).unwrap()).unwrap();
    let arrays = data_arrays(&xml);
    let g = arrays.iter().find(|(a, _)| attr(a, "Name") == Some("grad_c")).unwrap();
    assert_eq!(g.1.split_whitespace().count(), 12);
}

#[test]
fn pvd_lists_every_snapshot_and_is_rewritten() {
    let dir = tempfile::tempdir().unwrap();
    let mut pvd = PvdWriter::new(dir.path());
    let pvd_path = dir.path().join("particles.pvd");
    assert_eq!(pvd.path(), pvd_path);
    for (k, step) in [0u64, 100, 200, 300].into_iter().enumerate() {
        let vtu = pvd.add_snapshot(&snapshot(5, step)).unwrap();
        assert!(vtu.exists());
        // After each addition the file on disk is complete and lists everything so far.
        let xml = fs::read_to_string(&pvd_path).unwrap();
        assert_tags_balanced(&xml);
        assert!(xml.contains("type=\"Collection\""));
        assert_eq!(xml.matches("<DataSet").count(), k + 1);
        assert!(xml.contains(&format!("file=\"particles_{step:08}.vtu\"")));
    }
    let xml = fs::read_to_string(&pvd_path).unwrap();
    assert!(xml.contains("timestep=\"0.03\""));
    assert!(xml.contains("file=\"particles_00000000.vtu\""));
    assert_eq!(pvd.entries().len(), 4);
    // no temporary file left behind
    assert!(!dir.path().join("particles.pvd.tmp").exists());
    // plain add with a name needing escaping
    pvd.add(1.0, "a&b.vtu").unwrap();
    let xml = fs::read_to_string(&pvd_path).unwrap();
    assert!(xml.contains("file=\"a&amp;b.vtu\""));
    assert_tags_balanced(&xml);
}

// ---------------------------------------------------------------------------------------------
// Series CSV

#[derive(Serialize)]
struct Row {
    step: u64,
    t: f64,
    ke: f64,
    note: String,
}

#[test]
fn series_writer_flushes_every_row() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nested/series.csv");
    let mut w = SeriesWriter::create(&path).unwrap();
    // created, empty
    assert_eq!(fs::read_to_string(&path).unwrap(), "");
    for k in 0..5u64 {
        w.write(&Row {
            step: k,
            t: k as f64 * 0.5,
            ke: if k == 4 { f64::NAN } else { k as f64 },
            note: format!("r{k}"),
        })
        .unwrap();
        // read back while the writer is still alive
        let text = fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "step,t,ke,note");
        assert_eq!(lines.len() as u64, k + 2);
        assert!(lines.last().unwrap().starts_with(&format!("{k},")));
    }
    assert_eq!(w.rows(), 5);
    let text = fs::read_to_string(&path).unwrap();
    assert!(text.lines().nth(5).unwrap().contains("NaN"));
    assert_eq!(w.finish().unwrap(), path);
}

#[test]
fn series_writer_reports_bad_rows() {
    #[derive(Serialize)]
    struct Nested {
        a: Vec<Vec<u8>>,
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.csv");
    let mut w = SeriesWriter::create(&path).unwrap();
    let err = w.write(&Nested { a: vec![vec![1]] }).unwrap_err();
    assert!(err.to_string().contains("bad.csv"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// Summary

#[test]
fn json_summary_is_pretty_and_round_trips() {
    #[derive(Serialize)]
    struct Summary {
        name: &'static str,
        steps: u64,
        l2: f64,
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run/summary.json");
    write_json(&path, &Summary { name: "drop", steps: 10, l2: 1.5e-3 }).unwrap();
    let text = fs::read_to_string(&path).unwrap();
    assert!(text.contains("\n  \"steps\": 10"));
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["name"], "drop");
    assert_eq!(v["l2"], 1.5e-3);
}

#[test]
fn git_commit_env_override_and_fallback() {
    // The only test touching this variable.
    std::env::remove_var("SPHLAB_GIT_COMMIT");
    let c = output::git_commit();
    assert!(!c.is_empty() && !c.contains('\n'));
    assert_eq!(c, sphlab::provenance::commit_label(), "the commit baked in at build time");
    std::env::set_var("SPHLAB_GIT_COMMIT", "abc1234");
    assert_eq!(output::git_commit(), "abc1234");
    std::env::remove_var("SPHLAB_GIT_COMMIT");
}

#[test]
fn iso8601_of_known_epochs() {
    let known = [
        (0, "1970-01-01T00:00:00Z"),
        (-1, "1969-12-31T23:59:59Z"),
        (951_782_400, "2000-02-29T00:00:00Z"),
        (1_000_000_000, "2001-09-09T01:46:40Z"),
        (1_234_567_890, "2009-02-13T23:31:30Z"),
        (1_709_210_096, "2024-02-29T12:34:56Z"),
        (4_102_444_800, "2100-01-01T00:00:00Z"),
        (-2_208_988_800, "1900-01-01T00:00:00Z"),
        (253_402_300_799, "9999-12-31T23:59:59Z"),
    ];
    for (secs, want) in known {
        assert_eq!(iso8601_from_unix(secs), want, "{secs}");
    }
    // every day boundary for 800 years round-trips through the calendar in order
    let mut prev = (1969, 12, 31);
    for day in 0..(800 * 366) {
        let (y, m, d) = output::summary::civil_from_days(day);
        let next_ok = (y, m, d) == (prev.0, prev.1, prev.2 + 1)
            || ((y, m, d) == (prev.0, prev.1 + 1, 1))
            || ((y, m, d) == (prev.0 + 1, 1, 1) && prev.1 == 12 && prev.2 == 31);
        assert!(next_ok, "day {day}: {prev:?} -> {:?}", (y, m, d));
        prev = (y, m, d);
    }
    let now = now_utc_iso8601();
    assert_eq!(now.len(), 20, "{now}");
    assert!(now.ends_with('Z') && now.as_bytes()[10] == b'T');
    assert!(now.as_str() > "2024-01-01");
}

#[test]
fn progress_is_a_noop_without_terminal() {
    let p = Progress::new(100, "test");
    p.inc(10);
    p.set_message("halfway");
    p.set_message(format!("step {}", 50));
    p.finish();
    let h = Progress::hidden();
    assert!(!h.is_visible());
    h.inc(1);
    h.finish();
}

// ---------------------------------------------------------------------------------------------
// Plots

fn read_svg(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap();
    assert!(text.contains("<svg"), "not an SVG");
    assert!(text.len() > 2000, "SVG only {} bytes", text.len());
    text
}

#[test]
fn line_plot_has_title_labels_legend() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plots/energy.svg");
    let mut spec = PlotSpec::new("Kinetic energy of the drop", "t (s)", "E_k (J/m)");
    spec.series.push(Series::line("CPU f64", (0..50).map(|i| (i as f64 * 0.01, (i as f64 * 0.2).sin())).collect()));
    spec.series.push(Series::points("GPU f32", (0..50).map(|i| (i as f64 * 0.01, (i as f64 * 0.2).cos())).collect()));
    spec.series.push(Series::new("GPU tracked", vec![(0.0, 0.1), (0.1, 0.2), (0.2, 0.15)], Style::LinePoints));
    spec.refs.push(RefLine::horizontal("thesis value", 0.75));
    spec.refs.push(RefLine::vertical("t_end", 0.4));
    line_plot_svg(&path, &spec).unwrap();
    let svg = read_svg(&path);
    for s in [
        "Kinetic energy of the drop",
        "t (s)",
        "E_k (J/m)",
        "CPU f64",
        "GPU f32",
        "GPU tracked",
        "thesis value",
        "t_end",
    ] {
        assert!(svg.contains(s), "missing {s}");
    }
    // distinct colours for the first series
    assert!(svg.contains("#1F77B4") || svg.contains("#1f77b4") || svg.contains("31,119,180"));
    assert!(svg.contains("#FF7F0E") || svg.contains("#ff7f0e") || svg.contains("255,127,14"));
}

#[test]
fn log_log_plot_works() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scaling.svg");
    let mut spec = PlotSpec::new("Scaling", "particles N (-)", "time per step (s)");
    spec.log_x = true;
    spec.log_y = true;
    spec.series.push(Series::line_points("cpu", (2..8).map(|k| (10f64.powi(k), 1e-6 * 10f64.powi(k))).collect()));
    // non-positive and NaN points are skipped on log axes
    spec.series
        .push(Series::line_points("gpu", vec![(0.0, 1.0), (1e3, -1.0), (1e4, 1e-4), (f64::NAN, 1e-3), (1e6, 2e-3)]));
    spec.refs.push(RefLine::horizontal("budget", 1e-2));
    spec.refs.push(RefLine::horizontal("negative ref is skipped", -1.0));
    line_plot_svg(&path, &spec).unwrap();
    let svg = read_svg(&path);
    assert!(svg.contains("Scaling") && svg.contains("cpu") && svg.contains("gpu"));

    // An axis with neither end on a power of ten (the period error of the speed-vs-error plot,
    // 0.0075–0.18) labels each power of ten inside once and nothing else.
    let pts = vec![(8.7, 0.14, "a".to_string()), (20.4, 0.0108, "b".to_string())];
    let p = dir.path().join("errors.svg");
    scatter_labeled_svg(&p, "t", "time (s)", "error (-)", &pts, true, true).unwrap();
    let svg = read_svg(&p);
    let texts: Vec<&str> =
        svg.split("<text").skip(1).filter_map(|t| Some(t.split_once('>')?.1.split_once("</text>")?.0.trim())).collect();
    for (label, n) in [("0.1", 1), ("0.01", 1), ("10", 1), ("0.05", 0)] {
        assert_eq!(texts.iter().filter(|t| **t == label).count(), n, "label {label} in {texts:?}");
    }

    // single-axis log variants
    spec.log_y = false;
    line_plot_svg(dir.path().join("logx.svg"), &spec).unwrap();
    spec.log_x = false;
    spec.log_y = true;
    line_plot_svg(dir.path().join("logy.svg"), &spec).unwrap();
}

#[test]
fn empty_and_nan_series_do_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    // nothing at all
    let spec = PlotSpec::new("Empty", "x (m)", "y (m)");
    line_plot_svg(dir.path().join("empty.svg"), &spec).unwrap();
    // empty series, all-NaN series, one point, constant series
    let mut spec = PlotSpec::new("Degenerate", "x (m)", "y (m)");
    spec.series.push(Series::line("nothing", vec![]));
    spec.series.push(Series::line("all nan", vec![(f64::NAN, f64::NAN); 4]));
    spec.series.push(Series::points("one", vec![(1.0, 2.0)]));
    spec.series.push(Series::line(
        "with gaps",
        vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0), (3.0, f64::INFINITY), (4.0, 2.0)],
    ));
    line_plot_svg(dir.path().join("degenerate.svg"), &spec).unwrap();
    let svg = read_svg(&dir.path().join("degenerate.svg"));
    assert!(svg.contains("all nan") && svg.contains("with gaps"));
    // same on log axes
    spec.log_x = true;
    spec.log_y = true;
    line_plot_svg(dir.path().join("degenerate_log.svg"), &spec).unwrap();
    let mut c = PlotSpec::new("Constant", "x (m)", "y (m)");
    c.series.push(Series::line("flat", vec![(1.0, 5.0), (1.0, 5.0)]));
    line_plot_svg(dir.path().join("const.svg"), &c).unwrap();
    c.log_x = true;
    c.log_y = true;
    line_plot_svg(dir.path().join("const_log.svg"), &c).unwrap();
}

#[test]
fn fixed_ranges_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let mut spec = PlotSpec::new("Ranged", "x (m)", "y (m)");
    spec.series.push(Series::line("s", (0..20).map(|i| (i as f64, i as f64)).collect()));
    spec.x_range = Some((2.0, 10.0));
    spec.y_range = Some((0.0, 5.0));
    line_plot_svg(dir.path().join("ranged.svg"), &spec).unwrap();
    spec.y_range = Some((3.0, 3.0));
    let err = line_plot_svg(dir.path().join("bad.svg"), &spec).unwrap_err();
    assert!(matches!(err, OutputError::Plot { .. }));
    assert!(err.to_string().contains("bad.svg"));
    spec.y_range = Some((0.0, 5.0));
    spec.log_y = true;
    assert!(line_plot_svg(dir.path().join("bad_log.svg"), &spec).is_err());
}

#[test]
fn scatter_labeled_pareto() {
    let dir = tempfile::tempdir().unwrap();
    let pts = vec![
        (1.2e-3, 5.0e-2, "cpu-f64".to_string()),
        (4.0e-4, 7.0e-2, "cpu-f32".to_string()),
        (2.0e-5, 9.0e-2, "gpu-grid".to_string()),
        (1.0e-5, f64::NAN, "broken".to_string()),
        (0.0, 1.0, "zero".to_string()),
    ];
    let path = dir.path().join("pareto.svg");
    scatter_labeled_svg(&path, "Speed against error", "time per step (s)", "L2 error (-)", &pts, true, true).unwrap();
    let svg = read_svg(&path);
    for s in ["Speed against error", "cpu-f64", "cpu-f32", "gpu-grid", "L2 error (-)"] {
        assert!(svg.contains(s), "missing {s}");
    }
    assert!(!svg.contains("broken"));
    // linear axes, and no point at all
    scatter_labeled_svg(dir.path().join("lin.svg"), "t", "x (s)", "y (-)", &pts, false, false).unwrap();
    scatter_labeled_svg(dir.path().join("none.svg"), "t", "x (s)", "y (-)", &[], true, false).unwrap();
}

#[test]
fn tick_format_is_short() {
    assert_eq!(fmt_tick(0.30000000000000004), "0.3");
    assert_eq!(fmt_tick(0.0), "0");
    assert_eq!(fmt_tick(25.0), "25");
    assert_eq!(fmt_tick(1e-5), "1e-5");
    assert_eq!(fmt_tick(2.5e6), "2.5e6");
    assert_eq!(fmt_tick(-0.125), "-0.125");
}
