//! The `sphlab` command line: `run`, `scene`, `analytic`, `variants`, `verify`, `validate`,
//! `study`, `report`, `stability`, `forces` and `info` ([`cli`]). Exit codes mean one thing each
//! ([`sphlab::error::Error::exit_code`]): 0 success, 2 bad input of any kind (scene fields,
//! options, `--out`, variant ids, a resource plan over the limits), always before an output
//! directory is created; 3 a numerical blow-up naming step and particle; 130 an interrupt
//! (Ctrl-C) after a final snapshot and `status: "interrupted"`; 143 a termination signal; 1
//! anything else (an output that cannot be written, a failed verification).

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    match cli::dispatch(cli::Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let msg = e.to_string();
            if !msg.is_empty() {
                eprintln!("error: {msg}");
            }
            ExitCode::from(e.exit_code())
        }
    }
}
