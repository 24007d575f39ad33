//! `sphlab scene`: the built-in scenes listed, one printed as TOML, and the overrides that start
//! relax-60 at another contact angle.

use super::common::print_json;
use clap::Subcommand;
use sphlab::error::Error;
use sphlab::scene::builtin;

#[derive(Subcommand)]
pub enum SceneCmd {
    /// List the built-in scenes.
    List {
        /// JSON output.
        #[arg(long)]
        json: bool,
    },
    /// Print a built-in scene as TOML (edit it and pass the file to `sphlab run`).
    Show {
        /// Scene name.
        name: String,
    },
    /// Print the overrides (one `KEY=VALUE` a line, for `--set`) that start relax-60 at another
    /// contact angle: the cap of the half-disc's area meeting the wall at THETA (none at 90°).
    RelaxStart {
        /// Starting contact angle in degrees, in (0, 180).
        theta: f64,
    },
}

/// Runs the scene subcommand; an unknown scene or an angle out of range is bad input.
pub fn run(cmd: SceneCmd) -> Result<(), Error> {
    match cmd {
        SceneCmd::List { json } => list(json),
        SceneCmd::Show { name } => match builtin::builtin(&name) {
            Some(s) => print!("{}", s.to_toml()),
            None => {
                return Err(Error::input(format!("unknown scene `{name}` (built-in: {})", builtin::BUILTIN.join(", "))))
            }
        },
        SceneCmd::RelaxStart { theta } => {
            if !(theta > 0.0 && theta < 180.0) {
                return Err(Error::input(format!(
                    "THETA = {theta}: the starting contact angle must be in (0, 180) degrees"
                )));
            }
            for s in sphlab::validate::relax_start_sets(theta) {
                println!("{s}");
            }
        }
    }
    Ok(())
}

/// The built-in scenes with their descriptions.
fn list(json: bool) {
    let rows: Vec<(&str, String)> =
        builtin::BUILTIN.iter().map(|n| (*n, builtin::builtin(n).expect("built-in").description)).collect();
    if json {
        let v: Vec<serde_json::Value> =
            rows.iter().map(|(n, d)| serde_json::json!({"name": n, "description": d})).collect();
        print_json(&serde_json::json!({ "scenes": v }));
    } else {
        for (n, d) in rows {
            println!("{n:18} {d}");
        }
    }
}
