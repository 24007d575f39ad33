//! A validation case as data: the runs it makes (scene, overrides, end time), the plots and
//! tables it writes, and the notes that state its method ([`CaseSpec`]); and what it measures
//! on each run and across the runs, as the rows `quantity | sphlab | thesis | analytic |
//! difference | verdict` with the bound of each verdict ([`Case`]). One executor
//! ([`super::executor::execute`]) runs every case the same way.

use super::report::{CaseReport, RunRecord};
use super::{Ctx, RunSpec, ValidateError};
use crate::plot::PlotSpec;
use std::path::PathBuf;

/// One run of a case.
pub struct CaseRun {
    /// The run: scene, overrides, end time, snapshot cadence; its id names `runs/<id>`.
    pub spec: RunSpec<'static>,
    /// Label in rows, notes and plots.
    pub label: String,
    /// Other directories whose finished run of the same scene may be reused (another case's).
    pub also: Vec<PathBuf>,
}

impl CaseRun {
    /// A run labelled `label`, with no other directory to reuse from.
    pub fn new(spec: RunSpec<'static>, label: impl Into<String>) -> Self {
        CaseRun { spec, label: label.into(), also: Vec::new() }
    }
}

/// A plot of a case: its file name in the case directory and the plot, whose series the
/// measures fill.
pub struct CasePlot {
    /// File name (`*.svg`).
    pub file: &'static str,
    /// Title, axes, reference lines; series added by the case's measures.
    pub plot: PlotSpec,
}

/// A CSV table of a case: its file name, header, and the rows the measures add.
pub struct CaseTable {
    /// File name (`*.csv`).
    pub file: &'static str,
    /// Header line.
    pub header: String,
    /// Rows (non-finite values written empty).
    pub rows: Vec<Vec<f64>>,
}

/// What a case is, before any run: its name and reference, its runs in order, and its outputs.
pub struct CaseSpec {
    /// Case name (directory under the report root).
    pub name: &'static str,
    /// Thesis section and figures.
    pub reference: &'static str,
    /// The runs, in the order they are made.
    pub runs: Vec<CaseRun>,
    /// Reasons the case is not at full resolution, known before any run.
    pub not_full: Vec<String>,
    /// The plots, written in this order after the measures.
    pub plots: Vec<CasePlot>,
    /// The tables, written after the plots.
    pub tables: Vec<CaseTable>,
    /// Notes on the method (what is measured and how), after the measures' notes.
    pub method_notes: Vec<String>,
}

/// A case's report while it is measured: the report, and the plots and tables it will write.
pub struct CaseOutput {
    /// The report (rows, runs, notes).
    pub rep: CaseReport,
    /// The plots of the spec.
    pub plots: Vec<CasePlot>,
    /// The tables of the spec.
    pub tables: Vec<CaseTable>,
}

impl CaseOutput {
    /// The plot written to `file` (a case's own spec names it: a missing one is a bug).
    pub fn plot(&mut self, file: &str) -> &mut PlotSpec {
        &mut self.plots.iter_mut().find(|p| p.file == file).expect("a plot of the case's spec").plot
    }

    /// The table written to `file`.
    pub fn table(&mut self, file: &str) -> &mut Vec<Vec<f64>> {
        &mut self.tables.iter_mut().find(|t| t.file == file).expect("a table of the case's spec").rows
    }
}

/// What a case measures: on each run, and across its runs. The executor calls
/// [`Case::spec`], then [`Case::measure`] (or [`Case::skipped`]) per run in order, then
/// [`Case::compare`].
pub trait Case {
    /// The case's runs and outputs under the options of `ctx`.
    fn spec(&self, ctx: &Ctx) -> CaseSpec;

    /// The measures and rows of one finished run (the executor records the run after it).
    fn measure(&mut self, ctx: &Ctx, run: &CaseRun, rec: &RunRecord, out: &mut CaseOutput)
        -> Result<(), ValidateError>;

    /// A run not made (`--skip-missing` without a finished run, or `--only` another run): the
    /// case is then not at full resolution.
    fn skipped(&mut self, _run: &CaseRun, id: &str, out: &mut CaseOutput) {
        out.rep.not_full_because(format!("{id} not run (time)"));
    }

    /// Rows and notes across the runs (ratios, comparisons), after the last run.
    fn compare(&mut self, _ctx: &Ctx, _out: &mut CaseOutput) -> Result<(), ValidateError> {
        Ok(())
    }
}
