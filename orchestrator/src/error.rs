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
    /// A search refused because its parameters let robots collide where
    /// its algorithm promises they never do (`check`'s S0; exit 4).
    #[error("{0}")]
    Collision(String),
    /// A recorded file (a run directory's) that is missing or malformed.
    #[error("cannot read `{}`: {message}", path.display())]
    Read { path: PathBuf, message: String },
}

pub type Result<T> = std::result::Result<T, Error>;

/// Exit status of a command that ran but whose answer is no: a search
/// that ended incomplete (`simulate`, `run`: every robot failed, cut off,
/// the round limit) or an assumption that fails (`check`).
pub const EXIT_INCOMPLETE: u8 = 3;

/// Exit status of a search in which robots collided under an algorithm
/// that promises they never do (every grid rule but RU), or that was
/// refused because its parameters would let them (`check`'s S0).
pub const EXIT_COLLISION: u8 = 4;

/// Exit status of a search that went past a stated bound (ARCHITECTURE.md,
/// "Bounds") and stalled there: `ended_by` `past_bound`, its headline
/// naming the bound and the robots.
pub const EXIT_PAST_BOUND: u8 = 5;

/// Whether robots collided in a run whose algorithm promises they never do.
pub fn collided(r: &gridswarm::outcome::RunResult) -> bool {
    r.algorithm.collision_free() && r.collisions > 0
}

/// A search's exit status: [`EXIT_COLLISION`] if it [`collided`] (even if
/// it found everything), else 0 if it completed, [`EXIT_PAST_BOUND`] if it
/// ended `past_bound`, [`EXIT_INCOMPLETE`] if it ended otherwise.
pub fn search_status(r: &gridswarm::outcome::RunResult) -> u8 {
    if collided(r) {
        EXIT_COLLISION
    } else if r.protocol.ended_by == "past_bound" {
        EXIT_PAST_BOUND
    } else if r.complete {
        0
    } else {
        EXIT_INCOMPLETE
    }
}

impl Error {
    /// The process exit status for this error: 2 for usage errors, 4 for a
    /// search refused for its collisions, 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Usage(_) => 2,
            Error::Collision(_) => EXIT_COLLISION,
            _ => 1,
        }
    }

    pub fn write(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Error {
        let path = path.into();
        move |source| Error::Write { path, source }
    }
}
