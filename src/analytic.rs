//! Analytic maximum-spread models of a drop impacting a wall (thesis §5.1, Table 1).
//!
//! Energy balance of an infinite liquid cylinder of diameter D0 hitting a wall at V0 (thesis
//! T85–T93, equations reconstructed in docs/PHYSICS.md §11). Energies are per unit length
//! divided by σD0; only Re = ρV0D0/μ, We = ρV0²D0/σ and the contact angle θ (radians) matter:
//!
//! ```text
//! (π/8)·We + π  =  ξ·(1 − cos θ) + W(ξ),        ξ = D_max/D0
//! ```
//!
//! * [`spread_axisym`]: axisymmetric model of Pasandideh-Fard et al. (1996), the reference;
//! * [`spread_2d_a`]: 2D with Pasandideh-Fard's assumptions, W = πWe·ξ/(2.4·√(2Re));
//! * [`spread_2d_b`]: 2D with Chandra & Avedisian's assumptions, W = (We/Re)·ξ²;
//! * [`spread_2d_c`]: the thesis's eq. (93), viscous layer min(h, δ) with two branches
//!   (eq. 92 for h > δ, eq. 91 for h < δ).
//!
//! [`table1`] is Table 1 of the thesis (`data/table1.csv`, embedded) and
//! [`table1_comparison`] recomputes it.
//!
//! [`capillary_wave`]: Prosperetti's (1981) initial-value solution of a standing capillary
//! wave (docs/PHYSICS.md §14), on the complex functions of [`complex`].

pub mod capillary_wave;
pub mod complex;

use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, SQRT_2};
use std::fmt::Write as _;

/// Bad input to a spread model.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum AnalyticError {
    #[error("Reynolds number `re` must be finite and > 0, got {0}")]
    InvalidRe(f64),
    #[error("Weber number `we` must be finite and >= 0, got {0}")]
    InvalidWe(f64),
    #[error("contact angle `theta_rad` must be finite and in (0, π) rad, got {0}")]
    InvalidTheta(f64),
}

/// Which form of the viscous work model (c) uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Branch {
    /// h > δ (eq. 92): boundary layer inside the film, uniform velocity above it.
    ThickFilm,
    /// h < δ (eq. 91): linear velocity profile over the whole film.
    ThinFilm,
}

impl std::fmt::Display for Branch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Branch::ThickFilm => "h > δ",
            Branch::ThinFilm => "h < δ",
        })
    }
}

/// Result of model (c): the spread factor, the branch used and h/δ at the maximum spread.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpreadC {
    pub xi: f64,
    pub branch: Branch,
    pub h_over_delta: f64,
}

fn check(re: f64, we: f64, theta_rad: f64) -> Result<(), AnalyticError> {
    if !(re.is_finite() && re > 0.0) {
        return Err(AnalyticError::InvalidRe(re));
    }
    if !(we.is_finite() && we >= 0.0) {
        return Err(AnalyticError::InvalidWe(we));
    }
    if !(theta_rad.is_finite() && theta_rad > 0.0 && theta_rad < PI) {
        return Err(AnalyticError::InvalidTheta(theta_rad));
    }
    Ok(())
}

/// Initial energy (kinetic + surface), (π/8)·We + π.
fn initial_energy(we: f64) -> f64 {
    PI * we / 8.0 + PI
}

/// Axisymmetric model (Pasandideh-Fard et al. 1996):
/// ξ = sqrt((We + 12) / (3(1 − cos θ) + 4·We/√Re)).
pub fn spread_axisym(re: f64, we: f64, theta_rad: f64) -> Result<f64, AnalyticError> {
    check(re, we, theta_rad)?;
    Ok(((we + 12.0) / (3.0 * (1.0 - theta_rad.cos()) + 4.0 * we / re.sqrt())).sqrt())
}

/// 2D model (a), Pasandideh-Fard assumptions:
/// ξ = π(We/8 + 1) / ((1 − cos θ) + π·We/(2.4·√(2Re))).
pub fn spread_2d_a(re: f64, we: f64, theta_rad: f64) -> Result<f64, AnalyticError> {
    check(re, we, theta_rad)?;
    Ok(initial_energy(we) / ((1.0 - theta_rad.cos()) + PI * we / (2.4 * (2.0 * re).sqrt())))
}

/// 2D model (b), Chandra & Avedisian assumptions: positive root of
/// (We/Re)·ξ² + (1 − cos θ)·ξ − π(We/8 + 1) = 0.
pub fn spread_2d_b(re: f64, we: f64, theta_rad: f64) -> Result<f64, AnalyticError> {
    check(re, we, theta_rad)?;
    let (a, b, c) = (we / re, 1.0 - theta_rad.cos(), initial_energy(we));
    if a == 0.0 {
        return Ok(c / b);
    }
    // Cancellation-free form of (−b + sqrt(b² + 4ac)) / 2a.
    Ok(2.0 * c / (b + (b * b + 4.0 * a * c).sqrt()))
}

/// Film thickness over boundary-layer thickness at spread ξ:
/// h/δ = (π/(4ξ))·√(2Re)/2.4.
pub fn h_over_delta(re: f64, xi: f64) -> f64 {
    PI / (4.0 * xi) * (2.0 * re).sqrt() / 2.4
}

/// Viscous work W(ξ)/(σD0) of model (c) in the given branch. The thick-film form is infinite
/// at and beyond its pole (w ≤ 0, i.e. h/δ ≤ 1/2).
pub fn viscous_work_2d_c(re: f64, we: f64, xi: f64, branch: Branch) -> f64 {
    match branch {
        Branch::ThickFilm => {
            let w = 1.0 - 2.4 * SQRT_2 * xi / (PI * re.sqrt());
            if w <= 0.0 {
                return f64::INFINITY;
            }
            SQRT_2 * we * xi.powi(3) / (4.8 * PI * re.sqrt() * w * w)
        }
        Branch::ThinFilm => 8.0 / (PI * PI) * (we / re) * xi.powi(4),
    }
}

/// Solves the model-(c) balance in one branch by bisection (inputs already checked).
fn solve_c(re: f64, we: f64, theta_rad: f64, branch: Branch) -> f64 {
    let k = 1.0 - theta_rad.cos();
    let e = initial_energy(we);
    if we == 0.0 {
        return e / k; // no viscous work in either branch
    }
    let balance = |xi: f64| k * xi + viscous_work_2d_c(re, we, xi, branch) - e;
    // The root lies below e/k (W ≥ 0) and, for h > δ, below the pole at w = 0.
    let mut hi = e / k;
    if branch == Branch::ThickFilm {
        hi = hi.min(PI * re.sqrt() / (2.4 * SQRT_2));
    }
    let mut lo = 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if balance(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// 2D model (c), one branch only (both are plotted in the thesis's Fig. 5.5).
pub fn spread_2d_c_branch(re: f64, we: f64, theta_rad: f64, branch: Branch) -> Result<f64, AnalyticError> {
    check(re, we, theta_rad)?;
    Ok(solve_c(re, we, theta_rad, branch))
}

/// 2D model (c), eq. (93): solve with the h > δ form; if that solution has h/δ < 1, solve
/// again with the h < δ form.
pub fn spread_2d_c(re: f64, we: f64, theta_rad: f64) -> Result<SpreadC, AnalyticError> {
    check(re, we, theta_rad)?;
    let mut branch = Branch::ThickFilm;
    let mut xi = solve_c(re, we, theta_rad, branch);
    if h_over_delta(re, xi) < 1.0 {
        branch = Branch::ThinFilm;
        xi = solve_c(re, we, theta_rad, branch);
    }
    Ok(SpreadC { xi, branch, h_over_delta: h_over_delta(re, xi) })
}

/// All models at one (Re, We, θ).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpreadResult {
    pub re: f64,
    pub we: f64,
    pub theta_rad: f64,
    pub theta_deg: f64,
    pub axisym: f64,
    pub model_a: f64,
    pub model_b: f64,
    pub model_c: f64,
    pub model_c_branch: Branch,
    pub model_c_h_over_delta: f64,
    pub model_c_thick: f64,
    pub model_c_thin: f64,
}

/// Evaluates every model at (Re, We, θ).
pub fn spread_all(re: f64, we: f64, theta_rad: f64) -> Result<SpreadResult, AnalyticError> {
    let c = spread_2d_c(re, we, theta_rad)?;
    Ok(SpreadResult {
        re,
        we,
        theta_rad,
        theta_deg: theta_rad.to_degrees(),
        axisym: spread_axisym(re, we, theta_rad)?,
        model_a: spread_2d_a(re, we, theta_rad)?,
        model_b: spread_2d_b(re, we, theta_rad)?,
        model_c: c.xi,
        model_c_branch: c.branch,
        model_c_h_over_delta: c.h_over_delta,
        model_c_thick: solve_c(re, we, theta_rad, Branch::ThickFilm),
        model_c_thin: solve_c(re, we, theta_rad, Branch::ThinFilm),
    })
}

/// One row of thesis Table 1 (columns of `data/table1.csv`). Units as printed: V0 in m/s, D0
/// in mm except the rows of ref. [2] (printed in m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Table1Row {
    pub re: f64,
    pub we: f64,
    pub theta_rad: f64,
    pub v0: f64,
    pub d0: f64,
    pub axisym: f64,
    pub model_a: f64,
    pub model_b: f64,
    pub model_c: f64,
    pub measured: f64,
    #[serde(rename = "ref")]
    pub reference: String,
}

const TABLE1_CSV: &str = include_str!("../data/table1.csv");

/// Thesis Table 1, all 33 rows, in printed order.
pub fn table1() -> Vec<Table1Row> {
    csv::Reader::from_reader(TABLE1_CSV.as_bytes())
        .deserialize()
        .collect::<Result<_, _>>()
        .expect("embedded data/table1.csv is valid")
}

/// One model cell: thesis value, sphlab value and signed relative error (sphlab/thesis − 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CellComparison {
    pub thesis: f64,
    pub sphlab: f64,
    pub rel_error: f64,
}

impl CellComparison {
    fn new(thesis: f64, sphlab: f64) -> Self {
        Self { thesis, sphlab, rel_error: sphlab / thesis - 1.0 }
    }
}

/// A Table 1 row recomputed by sphlab.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table1Comparison {
    pub row: Table1Row,
    pub axisym: CellComparison,
    pub model_a: CellComparison,
    pub model_b: CellComparison,
    pub model_c: CellComparison,
}

impl Table1Comparison {
    /// The four model cells with their column names.
    pub fn cells(&self) -> [(&'static str, CellComparison); 4] {
        [("axisym", self.axisym), ("model_a", self.model_a), ("model_b", self.model_b), ("model_c", self.model_c)]
    }
}

/// Every row of Table 1 recomputed, with relative errors against the thesis.
pub fn table1_comparison() -> Vec<Table1Comparison> {
    table1()
        .into_iter()
        .map(|row| {
            let s = spread_all(row.re, row.we, row.theta_rad).expect("Table 1 inputs are valid");
            Table1Comparison {
                axisym: CellComparison::new(row.axisym, s.axisym),
                model_a: CellComparison::new(row.model_a, s.model_a),
                model_b: CellComparison::new(row.model_b, s.model_b),
                model_c: CellComparison::new(row.model_c, s.model_c),
                row,
            }
        })
        .collect()
}

/// The cell with the largest |relative error|: (row index, column name, cell).
pub fn worst_cell(rows: &[Table1Comparison]) -> Option<(usize, &'static str, CellComparison)> {
    rows.iter()
        .enumerate()
        .flat_map(|(i, r)| r.cells().map(|(name, c)| (i, name, c)))
        .max_by(|a, b| a.2.rel_error.abs().total_cmp(&b.2.rel_error.abs()))
}

/// Human-readable summary of [`spread_all`].
pub fn format_spread(s: &SpreadResult) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "Maximum spread D_max/D0 (thesis §5.1)");
    let _ = writeln!(o, "  Re = {}   We = {}   θ = {:.2}° ({:.4} rad)", s.re, s.we, s.theta_deg, s.theta_rad);
    let lines = [
        ("axisymmetric (Pasandideh-Fard 1996)", s.axisym),
        ("2D (a) Pasandideh-Fard assumptions", s.model_a),
        ("2D (b) Chandra & Avedisian assumptions", s.model_b),
    ];
    for (name, v) in lines {
        let _ = writeln!(o, "  {name:<40} {v:>8.3}");
    }
    let _ = writeln!(
        o,
        "  {:<40} {:>8.3}   [{}, h/δ = {:.3}]",
        "2D (c) eq. (93)", s.model_c, s.model_c_branch, s.model_c_h_over_delta
    );
    let _ = writeln!(o, "  {:<40} {:>8.3}", "    branch h > δ (eq. 92)", s.model_c_thick);
    let _ = writeln!(o, "  {:<40} {:>8.3}", "    branch h < δ (eq. 91)", s.model_c_thin);
    o
}

/// A thesis value as printed: two decimals, more only where the thesis prints more.
fn printed(v: f64) -> String {
    let s = format!("{v:.2}");
    if s.parse::<f64>() == Ok(v) {
        s
    } else {
        v.to_string()
    }
}

/// Table 1 as thesis | sphlab | relative error for each model column, with the worst cell.
pub fn format_table1(rows: &[Table1Comparison]) -> String {
    let mut o = String::new();
    let _ = write!(o, "{:>6} {:>4} {:>6} {:>5}", "Re", "We", "θ(rad)", "ref");
    for name in ["axisym", "(a)", "(b)", "(c)"] {
        let _ = write!(o, " | {name:^24}");
    }
    let _ = write!(o, "\n{:>24}", "");
    for _ in 0..4 {
        let _ = write!(o, " | {:>7} {:>7} {:>8}", "thesis", "sphlab", "rel.err");
    }
    o.push('\n');
    for r in rows {
        let row = &r.row;
        let _ = write!(o, "{:>6} {:>4} {:>6} {:>5}", row.re, row.we, row.theta_rad, row.reference);
        for (_, c) in r.cells() {
            let _ = write!(o, " | {:>7} {:>7.3} {:>+7.2}%", printed(c.thesis), c.sphlab, 100.0 * c.rel_error);
        }
        o.push('\n');
    }
    if let Some((i, name, c)) = worst_cell(rows) {
        let _ = writeln!(
            o,
            "max |rel. error| = {:.3} % ({name}, row {} Re = {}: thesis {}, sphlab {:.4})",
            100.0 * c.rel_error.abs(),
            i + 1,
            rows[i].row.re,
            c.thesis,
            c.sphlab
        );
    }
    o
}
