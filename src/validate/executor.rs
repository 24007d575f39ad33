//! The one executor of the validation cases: makes (or reuses) a case's runs in order, hands each
//! to the case's measures, then writes the plots and tables its spec declares and appends the
//! notes on its method.

use super::case::{Case, CaseOutput};
use super::report::{plot, write_csv, CaseReport};
use super::{Ctx, ValidateError};

/// Runs `case` under the options of `ctx` and returns its report (written by the caller).
pub fn execute(ctx: &Ctx, case: &mut dyn Case) -> Result<CaseReport, ValidateError> {
    let spec = case.spec(ctx);
    let mut out = CaseOutput {
        rep: CaseReport::new(spec.name, spec.reference, ctx.opts.quick),
        plots: spec.plots,
        tables: spec.tables,
    };
    for why in spec.not_full {
        out.rep.not_full_because(why);
    }
    for run in &spec.runs {
        match ctx.run(&run.spec, &run.also) {
            Ok(rec) => {
                case.measure(ctx, run, &rec, &mut out)?;
                out.rep.runs.push(rec);
            }
            Err(ValidateError::Skipped(id)) => case.skipped(run, &id, &mut out),
            Err(e) => return Err(e),
        }
    }
    case.compare(ctx, &mut out)?;
    let CaseOutput { mut rep, plots, tables } = out;
    for p in &plots {
        plot(ctx, &mut rep, p.file, &p.plot)?;
    }
    for t in &tables {
        write_csv(ctx, &mut rep, t.file, &t.header, &t.rows)?;
    }
    rep.notes.extend(spec.method_notes);
    Ok(rep)
}
