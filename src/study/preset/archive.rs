//! What the GPU preset leaves behind, rewritten after every part so a kill loses at most the
//! part in flight: `summary.md` (each part's share, time, status and result), `parts.json`,
//! and with `--archive DIR` the whole report as `DIR/gpu-report.tar.gz` (written to a temporary
//! name and renamed, so a reader never sees half an archive) plus `DIR/summary.md`. Per-step
//! particle snapshots are left out so the archive stays small.

use serde::Serialize;
use std::fmt::Write as _;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The archive's file name.
pub const ARCHIVE: &str = "gpu-report.tar.gz";

/// How one part ended.
#[derive(Clone, Debug, Serialize)]
pub struct Outcome {
    /// Directory name under `parts/`.
    pub name: String,
    /// What it runs.
    pub what: String,
    /// The `sphlab` command line.
    pub command: String,
    /// Its share of the budget (s); 0 when not reached.
    pub share_s: f64,
    /// Wall time it took (s).
    pub used_s: f64,
    /// `done`, `failed`, `cut` (stopped at the end of its share), `skipped`, `interrupted`
    /// (SIGINT/SIGTERM), `running` (in flight when the archive was written) or `pending`.
    pub status: String,
    /// Why it was skipped, failed or cut, or what it found.
    pub note: String,
}

impl Outcome {
    /// A part not reached yet.
    pub fn pending(name: &str, what: &str) -> Outcome {
        Outcome {
            name: name.into(),
            what: what.into(),
            command: String::new(),
            share_s: 0.0,
            used_s: 0.0,
            status: "pending".into(),
            note: String::new(),
        }
    }
}

/// What a finished part produced, in one line: records and how many are `ok` for a study,
/// the verdicts for a verification, the timings of the walk probe, each run's status, steps, simulated time and ms/step for a
/// validation (`<case>/runs/<id>/summary.json`: a blow-up is named, not hidden), the last lines
/// of its log otherwise.
pub fn result_line(dir: &Path) -> String {
    let records = ["records.csv", super::super::report::JOURNAL].iter().map(|f| dir.join(f)).find(|p| p.exists());
    if let Some(p) = records {
        if let Ok(mut r) = csv::Reader::from_path(&p) {
            let status = r.headers().ok().and_then(|h| h.iter().position(|c| c == "status"));
            let rows: Vec<csv::StringRecord> = r.records().filter_map(Result::ok).collect();
            let ok = status.map_or(0, |k| rows.iter().filter(|x| x.get(k) == Some("ok")).count());
            let file = p.file_name().map(|f| f.to_string_lossy().to_string()).unwrap_or_default();
            return format!("{} records ({ok} ok) in {file}", rows.len());
        }
    }
    if let Ok(text) = std::fs::read_to_string(dir.join("verify.json")) {
        if let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) {
            let mut counts = std::collections::BTreeMap::<String, usize>::new();
            for r in v["variants"].as_array().into_iter().flatten() {
                *counts.entry(r["status"].as_str().unwrap_or("?").to_string()).or_default() += 1;
            }
            let parts: Vec<String> = counts.iter().map(|(s, n)| format!("{n} {s}")).collect();
            return format!("verify: {}", parts.join(", "));
        }
    }
    if let Ok(mut r) = csv::Reader::from_path(dir.join("walk.csv")) {
        return format!("{} walk timings in walk.csv", r.records().filter_map(Result::ok).count());
    }
    let runs = validation_runs(dir);
    if !runs.is_empty() {
        return runs.join(" / ");
    }
    let log = last_lines(&dir.join("log.txt"), 2);
    if log.is_empty() {
        "no output yet".into()
    } else {
        log
    }
}

/// One line per run of a validation part (`<case>/runs/<id>/summary.json`), in name order:
/// `case id: status, steps to t = … s, ms/step` (the status cut at its first sentence).
fn validation_runs(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut cases: Vec<PathBuf> = std::fs::read_dir(dir).into_iter().flatten().flatten().map(|e| e.path()).collect();
    cases.sort();
    for case in cases.iter().filter(|c| c.join("runs").is_dir()) {
        let mut runs: Vec<PathBuf> =
            std::fs::read_dir(case.join("runs")).into_iter().flatten().flatten().map(|e| e.path()).collect();
        runs.sort();
        for run in runs {
            let Ok(text) = std::fs::read_to_string(run.join("summary.json")) else { continue };
            let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else { continue };
            let name = |p: &Path| p.file_name().map(|f| f.to_string_lossy().to_string()).unwrap_or_default();
            let status = v["status"].as_str().unwrap_or("?");
            let status = status.split(": at the output rows").next().unwrap_or(status);
            out.push(format!(
                "{} {}: {status}; {} steps to t = {:.3e} s, {:.3} ms/step",
                name(case),
                name(&run),
                v["steps"].as_u64().unwrap_or(0),
                v["t_final"].as_f64().unwrap_or(f64::NAN),
                v["ms_per_step"].as_f64().unwrap_or(f64::NAN)
            ));
        }
    }
    out
}

/// The last `n` non-empty lines of a log, joined by " / ".
pub fn last_lines(p: &Path, n: usize) -> String {
    let text = std::fs::read_to_string(p).unwrap_or_default();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    lines[lines.len().saturating_sub(n)..].join(" / ")
}

/// The report's header facts.
pub struct Header<'a> {
    /// The adapter line (name, backend, type, driver).
    pub adapter: &'a str,
    /// The scale (`gpu`, `rehearsal`).
    pub scale: &'a str,
    /// The budget (s).
    pub budget_s: f64,
    /// Commit and date lines.
    pub provenance: &'a str,
}

/// `summary.md`: the header, one row per part, the elapsed time and where things are.
pub fn summary(h: &Header, parts: &[Outcome], elapsed_s: f64, ending: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# GPU report: {}\n", h.adapter);
    let _ = writeln!(s, "{}", h.provenance);
    let _ = writeln!(
        s,
        "Scale: `{}`. Budget {:.0} s; {ending} after {elapsed_s:.0} s ({:.0} % of it).\n",
        h.scale,
        h.budget_s,
        100.0 * elapsed_s / h.budget_s.max(1e-9)
    );
    if h.scale != "gpu" {
        let _ = writeln!(s, "A CPU adapter: this run rehearses the pipeline; its times are no GPU measurement.\n");
    }
    let _ =
        writeln!(s, "| part | runs | share (s) | took (s) | status | result or reason |\n|---|---|---|---|---|---|");
    for p in parts {
        let _ = writeln!(
            s,
            "| `{}` | {} | {:.0} | {:.1} | {} | {} |",
            p.name,
            p.what,
            p.share_s,
            p.used_s,
            p.status,
            p.note.replace('|', "\\|")
        );
    }
    let _ = writeln!(
        s,
        "\nEach part's output and `log.txt` are under `parts/<part>/`, its command in `parts.json`; the study \
         parts are merged in `study/summary.md`; `provenance.json` names adapter, driver, limits, commit and the \
         binary's SHA-256."
    );
    s
}

/// SHA-256 of a file, hex.
pub fn sha256_of(p: &Path) -> Result<String, String> {
    use sha2::Digest;
    let mut f = std::fs::File::open(p).map_err(|e| format!("{}: {e}", p.display()))?;
    let mut h = sha2::Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = f.read(&mut buf).map_err(|e| format!("{}: {e}", p.display()))?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

/// Per-step particle snapshots and VTK files stay out of the archive.
fn archived(p: &Path) -> bool {
    let name = p.file_name().map(|f| f.to_string_lossy().to_string()).unwrap_or_default();
    !(name.starts_with("particles_") || name.ends_with(".vtu") || name.ends_with(".pvd") || name.ends_with(".tmp"))
}

fn add_dir(tar: &mut tar::Builder<impl std::io::Write>, dir: &Path, name: &Path) -> std::io::Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        let Some(file) = p.file_name() else { continue };
        let inner = name.join(file);
        if p.is_dir() {
            add_dir(tar, &p, &inner)?;
        } else if p.is_file() && archived(&p) {
            tar.append_path_with_name(&p, &inner)?;
        }
    }
    Ok(())
}

/// `archive/gpu-report.tar.gz` of `report_dir` (as `<its name>/…`) and `archive/summary.md`.
pub fn write(report_dir: &Path, archive: &Path, summary_md: &str) -> Result<u64, String> {
    let err = |e: std::io::Error| format!("{}: {e}", archive.display());
    std::fs::create_dir_all(archive).map_err(err)?;
    let tmp = archive.join(format!("{ARCHIVE}.tmp"));
    let root = PathBuf::from(report_dir.file_name().unwrap_or_default());
    {
        let f = std::fs::File::create(&tmp).map_err(err)?;
        let gz = flate2::write::GzEncoder::new(f, flate2::Compression::default());
        let mut tar = tar::Builder::new(gz);
        add_dir(&mut tar, report_dir, &root).map_err(err)?;
        tar.into_inner().map_err(err)?.finish().map_err(err)?;
    }
    std::fs::rename(&tmp, archive.join(ARCHIVE)).map_err(err)?;
    std::fs::write(archive.join("summary.md"), summary_md).map_err(err)?;
    Ok(std::fs::metadata(archive.join(ARCHIVE)).map_err(err)?.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_archive_holds_the_report_without_snapshots() {
        let d = tempfile::tempdir().unwrap();
        let rep = d.path().join("nvidia-h200");
        std::fs::create_dir_all(rep.join("parts/01-smoke")).unwrap();
        std::fs::write(rep.join("provenance.json"), "{}").unwrap();
        std::fs::write(rep.join("parts/01-smoke/verify.json"), r#"{"variants":[{"status":"pass"},{"status":"pass"}]}"#)
            .unwrap();
        std::fs::write(rep.join("parts/01-smoke/particles_000010.csv"), "x").unwrap();
        let out = d.path().join("out");
        write(&rep, &out, "# s\n").unwrap();
        let gz = flate2::read::GzDecoder::new(std::fs::File::open(out.join(ARCHIVE)).unwrap());
        let mut names: Vec<String> = tar::Archive::new(gz)
            .entries()
            .unwrap()
            .map(|e| e.unwrap().path().unwrap().display().to_string())
            .collect();
        names.sort();
        assert_eq!(names, ["nvidia-h200/parts/01-smoke/verify.json", "nvidia-h200/provenance.json"]);
        assert_eq!(std::fs::read_to_string(out.join("summary.md")).unwrap(), "# s\n");
        assert_eq!(result_line(&rep.join("parts/01-smoke")), "verify: 2 pass");
        assert!(!out.join(format!("{ARCHIVE}.tmp")).exists());
    }

    #[test]
    fn a_validation_part_names_each_runs_status() {
        let d = tempfile::tempdir().unwrap();
        let run = d.path().join("impact/runs/theta50");
        std::fs::create_dir_all(&run).unwrap();
        std::fs::write(d.path().join("log.txt"), "").unwrap();
        let status = "blow-up: blow-up at step 24452 (t = 2.488312e-4): particle 0 left the domain: at the output \
                      rows before it: largest CFL number 0.252";
        let json = serde_json::json!({"status": status, "steps": 24452, "t_final": 2.488e-4, "ms_per_step": 1.517});
        std::fs::write(run.join("summary.json"), json.to_string()).unwrap();
        assert_eq!(
            result_line(d.path()),
            "impact theta50: blow-up: blow-up at step 24452 (t = 2.488312e-4): particle 0 left the domain; 24452 \
             steps to t = 2.488e-4 s, 1.517 ms/step"
        );
    }
}
