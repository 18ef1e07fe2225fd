//! The `gridswarm` command as a library: every subcommand's work and the
//! writers other engines reuse (trajectories, summaries), so that `main.rs`
//! is only argument parsing and error printing.

pub mod check;
pub mod claims;
pub mod contract;
pub mod error;
pub mod experiment;
pub mod failures;
pub mod faults;
pub mod figures;
pub mod grids;
pub mod launch;
pub mod output;
pub mod panels;
pub mod plot;
pub mod radio;
pub mod replay;
pub mod report;
pub mod robots;
pub mod routes;
pub mod run;
pub mod scale;
pub mod rundir;
pub mod seeds;
pub mod simulate;
pub mod stats;
pub mod sweep;
pub mod tally;

pub use error::{Error, Result};
