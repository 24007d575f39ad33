//! [`Error`], the kind of failure that ends a command, and [`Error::exit_code`], the one place
//! where a kind becomes an exit code: 2 bad input, 1 a failed check or anything else, 3 a
//! numerical blow-up or an allocation failure, 130 an interrupt, 143 a termination signal.

use crate::run::RunError;
use crate::validate::ValidateError;
use std::fmt::Display;
use std::path::Path;

/// Why a command failed. Each kind carries the message printed as `error: …`; an empty message
/// prints nothing (the command's own output already said what happened).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input of any kind (a scene field, a flag, `--out`, a variant id, a resource plan over
    /// the limits), found before an output directory is created: exit 2.
    #[error("{0}")]
    Input(String),
    /// A check ran and did not pass (a GPU variant that disagrees, a failed smoke test): exit 1.
    #[error("{0}")]
    CheckFailed(String),
    /// A numerical blow-up or a buffer that could not be allocated mid-run: exit 3.
    #[error("{0}")]
    BlowUp(String),
    /// Stopped by an interrupt (SIGINT, Ctrl-C): exit 130.
    #[error("{0}")]
    Interrupted(String),
    /// Stopped by a termination signal (SIGTERM): exit 143.
    #[error("{0}")]
    Terminated(String),
    /// Anything else (an output that cannot be written, a failed run): exit 1.
    #[error("{0}")]
    Failed(String),
}

impl Error {
    /// Bad input with this message.
    pub fn input(msg: impl Display) -> Self {
        Error::Input(msg.to_string())
    }

    /// A failure of another kind with this message.
    pub fn failed(msg: impl Display) -> Self {
        Error::Failed(msg.to_string())
    }

    /// The process exit code of this kind.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input(_) => 2,
            Error::CheckFailed(_) | Error::Failed(_) => 1,
            Error::BlowUp(_) => 3,
            Error::Interrupted(_) => 130,
            Error::Terminated(_) => 143,
        }
    }

    /// The error of a `sphlab run` whose outputs are in `out`: a blow-up and an interrupt name
    /// the folder, which keeps the outputs written before them.
    pub fn from_run(e: RunError, out: &Path) -> Self {
        match e {
            e @ RunError::BlowUp(_) => Error::BlowUp(format!("{e}; outputs so far are in {}", out.display())),
            e @ RunError::Interrupted { .. } => Error::Interrupted(format!("{e} in {}", out.display())),
            e @ RunError::Alloc { .. } => Error::BlowUp(e.to_string()),
            e @ RunError::Input(_) => Error::Input(e.to_string()),
            e @ RunError::Output(_) => Error::Failed(e.to_string()),
        }
    }
}

impl From<ValidateError> for Error {
    /// An interrupted run stops the validation (130); bad input, the validation's own or a
    /// run's, is exit 2; any other failure, a blow-up included, exit 1.
    fn from(e: ValidateError) -> Self {
        match e {
            ValidateError::Run { err: RunError::Interrupted { .. }, id } => {
                Error::Interrupted(format!("run {id} interrupted"))
            }
            e @ ValidateError::Input(_) => Error::Input(e.to_string()),
            ValidateError::Run { err: e @ RunError::Input(_), id } => Error::Input(format!("run {id}: {e}")),
            e => Error::Failed(e.to_string()),
        }
    }
}
