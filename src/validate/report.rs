//! Validation reports: the comparison rows of a case, the provenance of its runs, and the
//! Markdown files (`<case>/summary.md`, `<case>/case.json`, `index.md`).

use super::{Ctx, ValidateError};
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

mod index;
pub use index::write_index;
pub(super) use index::{kernel_now, run_summary, summary_at};

/// One line of a case's comparison table.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    /// What is compared (with units).
    pub quantity: String,
    /// sphlab's value (formatted).
    pub sphlab: String,
    /// The thesis's value ("—" if it gives none).
    pub thesis: String,
    /// The analytic value ("—" if none).
    pub analytic: String,
    /// The difference to the analytic value and/or to the thesis.
    pub difference: String,
    /// pass / FAIL / invariant / info, with the criterion.
    pub verdict: String,
    /// The value as a number (for tests; NaN if none, written as `null` and read back as NaN).
    #[serde(deserialize_with = "nan_if_null")]
    pub value: f64,
}

/// A number, or NaN for the `null` serde_json writes for a non-finite one.
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

impl Row {
    /// A row; `difference` is computed against `reference` (relative) when given.
    pub fn new(quantity: &str, value: f64, prec: usize, thesis: Option<f64>, analytic: Option<f64>) -> Row {
        let f = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.prec$}"));
        let diff = |r: f64| {
            if !value.is_finite() {
                "—".to_string()
            } else if r != 0.0 {
                format!("{:+.prec$} ({:+.1} %)", value - r, 100.0 * (value - r) / r.abs())
            } else {
                format!("{:+.prec$}", value - r)
            }
        };
        let difference = match (thesis, analytic) {
            (Some(t), Some(a)) => format!("vs analytic {}; vs thesis {}", diff(a), diff(t)),
            (None, Some(a)) => diff(a),
            (Some(t), None) => diff(t),
            (None, None) => "—".into(),
        };
        Row {
            quantity: quantity.into(),
            sphlab: if value.is_finite() { format!("{value:.prec$}") } else { "n/a".into() },
            thesis: f(thesis),
            analytic: f(analytic),
            difference,
            verdict: "info".into(),
            value,
        }
    }

    /// Sets the thesis column to free text.
    pub fn thesis_text(mut self, s: &str) -> Row {
        self.thesis = s.into();
        self
    }

    /// Sets the analytic column to free text.
    pub fn analytic_text(mut self, s: &str) -> Row {
        self.analytic = s.into();
        self
    }

    /// Sets the sphlab column to free text (keeps the value).
    pub fn sphlab_text(mut self, s: String) -> Row {
        self.sphlab = s;
        self
    }

    /// Verdict from a test: "pass (criterion)" or "FAIL (criterion)".
    pub fn check(mut self, ok: bool, criterion: &str) -> Row {
        self.verdict = format!("{} ({criterion})", if ok { "pass" } else { "FAIL" });
        self
    }

    /// Names what a pass or FAIL depends on and, when committed runs give one, the result's
    /// sensitivity band: the verdict becomes "pass (criterion; depends on …; band …)". Applied
    /// again it replaces the earlier qualification (re-judging a committed report is idempotent);
    /// info, invariant and broken-invariant rows are left as they are.
    pub fn qualify(&mut self, depends_on: &str, band: Option<&Band>) {
        if self.is_qualified() && !self.verdict.contains(QUALIFIER) {
            return; // info, invariant, a broken invariant
        }
        let base = self.verdict.strip_suffix(')').unwrap_or(&self.verdict);
        let base = base.split(QUALIFIER).next().unwrap_or(base).to_string();
        let band = band.map_or("; no committed sensitivity run".to_string(), |b| format!("; {b}"));
        self.verdict = format!("{base}{QUALIFIER}{depends_on}{band})");
    }

    /// Whether a pass or FAIL verdict names what it depends on ([`Row::qualify`]); true for
    /// every other verdict (info, invariant, a broken invariant), which takes no qualification.
    pub fn is_qualified(&self) -> bool {
        let judged = (self.verdict.starts_with("pass (") || self.verdict.starts_with("FAIL ("))
            && !self.verdict.starts_with("FAIL (invariant broken");
        !judged || self.verdict.contains(QUALIFIER)
    }

    /// Whether the verdict is a pass (an invariant row is not).
    pub fn is_pass(&self) -> bool {
        self.verdict.starts_with("pass")
    }

    /// Verdict of a check true by construction (e.g. mass with fixed particle masses): "invariant
    /// (criterion)", or "FAIL (invariant broken: criterion)". Not counted as a pass in `index.md`:
    /// it guards the code, it does not validate the physics.
    pub fn invariant(mut self, ok: bool, criterion: &str) -> Row {
        self.verdict =
            if ok { format!("invariant ({criterion})") } else { format!("FAIL (invariant broken: {criterion})") };
        self
    }
}

/// The text between a verdict's criterion and what it depends on ([`Row::qualify`]).
const QUALIFIER: &str = "; depends on ";

/// A result's sensitivity band from committed runs: the parameter's values, the result at each,
/// the file(s) it was read from, and whether the verdict's bound holds across the whole band.
#[derive(Clone, Debug)]
pub struct Band {
    /// What was varied and where (e.g. "p_b × 0.5 / × 1 / × 2 at nx = 24").
    pub varied: String,
    /// The result at each value, formatted.
    pub values: Vec<String>,
    /// The committed file(s) read.
    pub source: String,
    /// Whether the bound holds at every value of the band (None: not judged).
    pub holds: Option<bool>,
}

impl std::fmt::Display for Band {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "sensitivity {}: {} ({})", self.varied, self.values.join(" / "), self.source)?;
        match self.holds {
            Some(true) => write!(f, ", bound met across the band"),
            Some(false) => write!(f, ", bound not met across the band"),
            None => Ok(()),
        }
    }
}

/// Provenance of one run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunRecord {
    /// Run id.
    pub id: String,
    /// Run directory.
    pub dir: String,
    /// Equivalent command line.
    pub command: String,
    /// Backend (cpu, cpu1, variant).
    pub backend: String,
    /// GPU variant id ("—" for the CPU backends).
    #[serde(default)]
    pub variant: String,
    /// Precision.
    pub precision: String,
    /// Adapter ("CPU" for the CPU backends).
    pub adapter: String,
    /// git commit of the binary.
    pub git_commit: String,
    /// Date (UTC).
    pub date: String,
    /// Wall time of the stepping (s).
    pub wall_time_s: f64,
    /// ms per step.
    pub ms_per_step: f64,
    /// Steps.
    pub steps: u64,
    /// Final time.
    pub t_final: f64,
    /// Fluid particles.
    pub n_fluid: usize,
    /// "ok" or the blow-up.
    pub status: String,
    /// Taken from an earlier run (`--reuse`).
    pub reused: bool,
}

impl RunRecord {
    /// Reads `dir/summary.json`.
    pub fn load(dir: &Path, command: &str, reused: bool) -> Option<RunRecord> {
        let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
        let v: serde_json::Value = serde_json::from_str(&text).ok()?;
        let s = |k: &str| v[k].as_str().unwrap_or("").to_string();
        let backend = s("backend");
        Some(RunRecord {
            id: dir.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default(),
            dir: dir.display().to_string(),
            command: command.into(),
            adapter: if backend.starts_with("cpu") { "CPU".into() } else { backend.clone() },
            backend,
            variant: v["options"]["variant"]
                .as_str()
                .or_else(|| v["options"]["backend"].as_str().filter(|b| !b.starts_with("cpu")))
                .unwrap_or("—")
                .to_string(),
            precision: s("precision"),
            // The provenance envelope (older summaries: top-level `git_commit`, `date`).
            git_commit: v["provenance"]["commit"].as_str().map_or_else(|| s("git_commit"), str::to_string),
            date: v["provenance"]["date"].as_str().map_or_else(|| s("date"), str::to_string),
            wall_time_s: v["wall_time_s"].as_f64().unwrap_or(f64::NAN),
            ms_per_step: v["ms_per_step"].as_f64().unwrap_or(f64::NAN),
            steps: v["steps"].as_u64().unwrap_or(0),
            t_final: v["t_final"].as_f64().unwrap_or(f64::NAN),
            n_fluid: v["particles_per_phase"]
                .as_array()
                .map(|a| a.iter().filter_map(|p| p[1].as_u64()).sum::<u64>() as usize)
                .unwrap_or(0),
            status: s("status"),
            reused,
        })
    }

    /// A finished (`ok`) run in `dir` of exactly `scene` to `t_end`, if there is one.
    pub fn reuse(dir: &Path, scene: &Scene, t_end: Option<f64>, command: &str) -> Option<RunRecord> {
        let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
        let mut v: serde_json::Value = serde_json::from_str(&text).ok()?;
        // Compared as run: the effective dt; the dt policy that produced it is not compared
        // (summaries from before `time.dt_policy` existed stay reusable).
        let applied = crate::scene::dt_policy::apply(scene).map_or_else(|_| scene.clone(), |a| a.scene);
        let mut want = serde_json::to_value(&applied).ok()?;
        // Read back through the scene type, so a field added since the run was written takes its
        // default (what the run ran with), as a scene file without it would.
        if let Ok(read) = serde_json::from_value::<Scene>(v["parameters"].clone()) {
            if let Ok(filled) = serde_json::to_value(&read) {
                v["parameters"] = filled;
            }
        }
        for j in [&mut v["parameters"]["time"], &mut want["time"]] {
            if let Some(t) = j.as_object_mut() {
                t.remove("dt_policy");
                t.remove("dt_nx");
            }
        }
        // The series cadence (`output.every`) changes no physics: a run written at another
        // cadence is reused, and its command shows the cadence it was run with.
        let mut command = command.to_string();
        let (got, wanted) = (v["parameters"]["output"]["every"].clone(), want["output"]["every"].clone());
        if got != wanted && got.is_u64() && wanted.is_u64() {
            command = command.replace(&format!("output.every={wanted}"), &format!("output.every={got}"));
            want["output"]["every"] = got;
        }
        let same_t = v["options"]["t_end"].as_f64() == t_end && v["options"]["steps"].is_null();
        // Floats compared to 1e-12 relative: serde_json's default parser is not always the
        // correctly rounded one (1 ulp off seen on a dt read back from summary.json).
        let differs = first_diff(&v["parameters"], &want, String::new());
        if v["status"] != "ok" || differs.is_some() || !same_t {
            if std::env::var_os("SPHLAB_DEBUG_REUSE").is_some() {
                eprintln!(
                    "no reuse of {}: status {}, same t_end {same_t}, first difference {:?}",
                    dir.display(),
                    v["status"],
                    first_diff(&v["parameters"], &want, String::new())
                );
            }
            return None;
        }
        RunRecord::load(dir, &command, true)
    }
}

/// The first path where two JSON values differ, with both values.
fn first_diff(a: &serde_json::Value, b: &serde_json::Value, path: String) -> Option<String> {
    match (a, b) {
        (serde_json::Value::Object(x), serde_json::Value::Object(y)) => x.keys().chain(y.keys()).find_map(|k| {
            first_diff(
                &x.get(k).cloned().unwrap_or_default(),
                &y.get(k).cloned().unwrap_or_default(),
                format!("{path}.{k}"),
            )
        }),
        (serde_json::Value::Array(x), serde_json::Value::Array(y)) if x.len() == y.len() => {
            x.iter().zip(y).enumerate().find_map(|(i, (p, q))| first_diff(p, q, format!("{path}[{i}]")))
        }
        (serde_json::Value::Number(x), serde_json::Value::Number(y))
            if x.as_f64().zip(y.as_f64()).is_some_and(|(p, q)| (p - q).abs() <= 1e-12 * p.abs().max(q.abs())) =>
        {
            None
        }
        _ if a == b => None,
        _ => Some(format!("{path}: {a} vs {b}")),
    }
}

/// Everything a case reports.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct CaseReport {
    /// Case name.
    pub name: String,
    /// Thesis section / figures.
    pub reference: String,
    /// Comparison rows.
    pub rows: Vec<Row>,
    /// Runs.
    pub runs: Vec<RunRecord>,
    /// Plots written (file names in the case directory).
    pub plots: Vec<String>,
    /// CSV files written besides the runs' series.
    pub csv: Vec<String>,
    /// Free-text notes.
    pub notes: Vec<String>,
    /// Why the case is not at full resolution (None: it is).
    pub not_full: Option<String>,
    /// `validate` wall time (s).
    pub wall_time_s: f64,
    /// Quick mode.
    pub quick: bool,
}

impl CaseReport {
    /// An empty report.
    pub fn new(name: &str, reference: &str, quick: bool) -> Self {
        CaseReport { name: name.into(), reference: reference.into(), quick, ..Default::default() }
    }

    /// The row whose quantity starts with `prefix` (for tests).
    pub fn row(&self, prefix: &str) -> Option<&Row> {
        self.rows.iter().find(|r| r.quantity.starts_with(prefix))
    }

    /// Adds a reason the case is not at full resolution.
    pub fn not_full_because(&mut self, why: String) {
        self.not_full = Some(match self.not_full.take() {
            Some(w) => format!("{w}; {why}"),
            None => why,
        });
    }
}

/// A table cell's text with its `|` escaped (quantities such as |θ − 60°| would split the cell).
pub(crate) fn cell(s: &str) -> String {
    s.replace('|', "\\|")
}

fn io(p: &Path, e: impl std::fmt::Display) -> ValidateError {
    ValidateError::Io(format!("{}: {e}", p.display()))
}

/// Writes `summary.md` and `case.json` of a case, and refreshes `index.md`.
pub fn write_summary(ctx: &Ctx, rep: &CaseReport) -> Result<(), ValidateError> {
    let mut m = String::new();
    let _ = writeln!(m, "# Validation: {}\n\n{}\n", rep.name, rep.reference);
    if let Some(w) = &rep.not_full {
        let _ = writeln!(m, "**Not at full resolution:** {w}\n");
    }
    let _ = writeln!(m, "| quantity | sphlab | thesis | analytic | difference | verdict |\n|---|---|---|---|---|---|");
    for r in &rep.rows {
        let _ = writeln!(
            m,
            "| {} | {} | {} | {} | {} | {} |",
            cell(&r.quantity),
            cell(&r.sphlab),
            cell(&r.thesis),
            cell(&r.analytic),
            cell(&r.difference),
            cell(&r.verdict)
        );
    }
    if !rep.notes.is_empty() {
        let _ = writeln!(m, "\n## Notes\n");
        for n in &rep.notes {
            let _ = writeln!(m, "* {n}");
        }
    }
    let _ = writeln!(m, "\n## Plots and data\n");
    for p in &rep.plots {
        let _ = writeln!(m, "* [{p}]({p})");
    }
    for c in &rep.csv {
        let _ = writeln!(m, "* [{c}]({c})");
    }
    let _ = writeln!(
        m,
        "\n## Runs\n\n| run | status | backend | variant | precision | adapter | particles | steps | t_end | wall time (s) | ms/step | commit | date | reused |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for r in &rep.runs {
        let _ = writeln!(
            m,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.4} | {:.1} | {:.3} | {} | {} | {} |",
            r.id,
            r.status,
            r.backend,
            r.variant,
            r.precision,
            r.adapter,
            r.n_fluid,
            r.steps,
            r.t_final,
            r.wall_time_s,
            r.ms_per_step,
            &r.git_commit,
            r.date,
            if r.reused { "yes" } else { "no" }
        );
    }
    let _ = writeln!(m, "\nCommands:\n");
    for r in &rep.runs {
        let _ = writeln!(m, "* `{}`: `{}`", r.id, r.command);
    }
    let _ = writeln!(
        m,
        "\n`sphlab validate {}{}` took {:.1} s (including reused runs' analysis).",
        rep.name,
        if rep.quick { " --quick" } else { "" },
        rep.wall_time_s
    );
    let p = ctx.path("summary.md");
    std::fs::write(&p, m).map_err(|e| io(&p, e))?;
    let j = ctx.path("case.json");
    std::fs::write(&j, serde_json::to_string_pretty(rep).expect("json")).map_err(|e| io(&j, e))?;
    write_index(ctx.opts, &[], &[])
}

/// Writes `name` (CSV with a header) in the case directory and records it.
pub fn write_csv(
    ctx: &Ctx,
    rep: &mut CaseReport,
    name: &str,
    header: &str,
    rows: &[Vec<f64>],
) -> Result<(), ValidateError> {
    let mut s = format!("{header}\n");
    for r in rows {
        let cells: Vec<String> = r.iter().map(|v| if v.is_finite() { format!("{v}") } else { String::new() }).collect();
        s += &cells.join(",");
        s.push('\n');
    }
    let p = ctx.path(name);
    std::fs::write(&p, s).map_err(|e| io(&p, e))?;
    rep.csv.push(name.into());
    Ok(())
}

/// Draws a line plot into the case directory and records it.
pub fn plot(ctx: &Ctx, rep: &mut CaseReport, name: &str, spec: &crate::plot::PlotSpec) -> Result<(), ValidateError> {
    let p = ctx.path(name);
    crate::plot::line_plot_svg(&p, spec).map_err(|e| io(&p, e))?;
    rep.plots.push(name.into());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::Row;

    #[test]
    fn a_row_without_a_value_reads_back_as_nan() {
        let row = Row::new("an extrapolation with no order", f64::NAN, 2, None, None);
        let text = serde_json::to_string(&row).unwrap();
        assert!(text.contains("\"value\":null"), "{text}");
        let back: Row = serde_json::from_str(&text).unwrap();
        assert!(back.value.is_nan());
        let finite: Row =
            serde_json::from_str(&serde_json::to_string(&Row::new("x", 1.5, 1, None, None)).unwrap()).unwrap();
        assert_eq!(finite.value, 1.5);
    }
}
