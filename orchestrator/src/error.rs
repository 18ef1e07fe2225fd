//! The command's error type: every failure the user can cause ends as one
//! `error: ...` line and a non-zero exit, never a panic.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scenario that cannot be loaded, validated or placed.
    #[error("{0}")]
    Scenario(String),
    /// A command-line value that parsed but does not fit the scenario.
    #[error("{0}")]
    Input(String),
    /// A combination of command-line flags that cannot be run (exit 2, as
    /// clap's own usage errors): a fault on a robot the run does not have,
    /// two failures for one robot, faults for a policy without a radio.
    #[error("{0}")]
    Usage(String),
    #[error("cannot create output directory `{}`: {source}", path.display())]
    OutDir { path: PathBuf, source: std::io::Error },
    #[error("cannot write `{}`: {source}", path.display())]
    Write { path: PathBuf, source: std::io::Error },
    #[error("cannot draw `{}`: {message}", path.display())]
    Plot { path: PathBuf, message: String },
    /// `gridswarm run`: a child process failed or the run was interrupted.
    #[error("{0}")]
    Run(String),
    /// A recorded file (a run directory's) that is missing or malformed.
    #[error("cannot read `{}`: {message}", path.display())]
    Read { path: PathBuf, message: String },
}

pub type Result<T> = std::result::Result<T, Error>;

/// Exit status of a command that ran but whose answer is no: a search
/// that ended incomplete (`simulate`, `run`: every robot failed, cut off,
/// the round limit) or an assumption that fails (`check`).
pub const EXIT_INCOMPLETE: u8 = 3;

impl Error {
    /// The process exit status for this error: 2 for usage errors, 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Usage(_) => 2,
            _ => 1,
        }
    }

    pub fn write(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Error {
        let path = path.into();
        move |source| Error::Write { path, source }
    }
}
