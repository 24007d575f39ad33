//! `sphlab analytic`: the analytic drop-spread models (thesis §5.1) for one impact, the
//! thesis's Table 1 beside sphlab's values, and Prosperetti's capillary-wave amplitude a(t)/a0
//! (docs/PHYSICS.md §14).

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
    /// Prosperetti's (1981) standing capillary wave: a(t)/a0 as CSV (`t,a_over_a0`), after
    /// comment lines with ω0, β and the slowest oscillatory root.
    CapillaryWave {
        /// Density of the lower fluid.
        #[arg(long, default_value_t = 1.0)]
        rho_lower: f64,
        /// Density of the upper fluid (0: a free surface).
        #[arg(long, default_value_t = 1.0)]
        rho_upper: f64,
        /// Kinematic viscosity, the same in both fluids (default: La = σρλ/μ² = 3000 at ρ = σ = λ = 1).
        #[arg(long, default_value_t = (1.0f64 / 3000.0).sqrt())]
        nu: f64,
        /// Surface tension σ.
        #[arg(long, default_value_t = 1.0)]
        sigma: f64,
        /// Wavelength λ.
        #[arg(long, default_value_t = 1.0)]
        wavelength: f64,
        /// End time (default: four inviscid periods).
        #[arg(long)]
        t_end: Option<f64>,
        /// Number of intervals between 0 and the end time.
        #[arg(long, default_value_t = 200)]
        samples: u32,
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
        AnalyticCmd::CapillaryWave { rho_lower, rho_upper, nu, sigma, wavelength, t_end, samples } => {
            use analytic::capillary_wave::{Prosperetti, WaveParams};
            let p =
                Prosperetti::new(WaveParams { rho_lower, rho_upper, nu, sigma, wavelength }).map_err(Error::input)?;
            let t_end = t_end.unwrap_or(4.0 * p.params.period0());
            if !(t_end.is_finite() && t_end > 0.0) {
                return Err(Error::input(format!("--t-end: must be a finite number > 0, got {t_end}")));
            }
            if samples == 0 || samples > 10_000_000 {
                return Err(Error::input(format!("--samples: must be in [1, 10000000], got {samples}")));
            }
            println!("# omega0 = {}, period0 = {}, beta = {}", p.params.omega0(), p.params.period0(), p.params.beta());
            if let Some((w, g)) = p.dominant_mode() {
                println!("# slowest oscillatory root: angular frequency {w}, decay rate {g}");
            }
            println!("t,a_over_a0");
            for i in 0..=samples {
                let t = t_end * i as f64 / samples as f64;
                println!("{t},{}", p.amplitude(t));
            }
        }
    }
    Ok(())
}
