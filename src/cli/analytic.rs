//! `sphlab analytic`: the analytic drop-spread models (thesis §5.1) for one impact, and the
//! thesis's Table 1 beside sphlab's values.

use super::common::{print_json, with_provenance};
use clap::{Subcommand, ValueEnum};
use sphlab::analytic;
use sphlab::error::Error;
use sphlab::provenance::{self, Provenance};

/// Analytic spread models.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Model {
    All,
    Axisym,
    A,
    B,
    C,
}

#[derive(Subcommand)]
pub enum AnalyticCmd {
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
        /// The model.
        #[arg(long, value_enum, default_value = "all")]
        model: Model,
        /// JSON output (with the provenance envelope).
        #[arg(long)]
        json: bool,
    },
    /// The thesis's Table 1 beside sphlab's values, with the relative error of each cell.
    Table1 {
        /// JSON output (with the provenance envelope).
        #[arg(long)]
        json: bool,
    },
}

/// Runs the analytic subcommand; numbers outside a model's range are bad input.
pub fn run(cmd: AnalyticCmd) -> Result<(), Error> {
    let prov = || Provenance::new("analytic", None, provenance::ANALYTIC_UNITS);
    match cmd {
        AnalyticCmd::Spread { re, we, theta_deg, theta_rad, model, json } => {
            let theta = theta_rad.unwrap_or_else(|| theta_deg.unwrap_or(f64::NAN).to_radians());
            let r = analytic::spread_all(re, we, theta).map_err(Error::input)?;
            if json {
                let v = match model {
                    Model::Axisym => serde_json::json!({"model": "axisym", "xi": r.axisym}),
                    Model::A => serde_json::json!({"model": "a", "xi": r.model_a}),
                    Model::B => serde_json::json!({"model": "b", "xi": r.model_b}),
                    Model::C => serde_json::json!({"model": "c", "xi": r.model_c}),
                    Model::All => serde_json::to_value(r).expect("serialisable"),
                };
                print_json(&with_provenance(v, &prov()));
            } else {
                match model {
                    Model::Axisym => println!("D_max/D0 (axisymmetric) = {:.4}", r.axisym),
                    Model::A => println!("D_max/D0 (2D a) = {:.4}", r.model_a),
                    Model::B => println!("D_max/D0 (2D b) = {:.4}", r.model_b),
                    Model::C => println!("D_max/D0 (2D c, eq. 93) = {:.4}", r.model_c),
                    Model::All => print!("{}", analytic::format_spread(&r)),
                }
            }
        }
        AnalyticCmd::Table1 { json } => {
            let rows = analytic::table1_comparison();
            if json {
                print_json(&with_provenance(serde_json::json!({ "rows": rows }), &prov()));
            } else {
                print!("{}", analytic::format_table1(&rows));
            }
        }
    }
    Ok(())
}
