//! The `gridswarm` command as a library, in five jobs, one folder each:
//! the command line (`cli`), experiments (`experiments`), process
//! supervision for distributed runs (`supervise`), writers (`write`), and
//! what made an output and repeating it (`provenance`).
//! `contract` wraps the shared crate's scenario and engine entry points
//! (other modules also call the library directly); `error` the errors
//! every job returns. The modules
//! are re-exported at the top so that every path reads `crate::run`,
//! `crate::report`, ...

/// Every program linking this library (the command, its benches and tests)
/// allocates through mimalloc: a sweep's runs create and drop millions of
/// small frames and vectors, and glibc's allocator cost about 10% more
/// instructions on them, more in wall time with several threads.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

pub mod cli;
pub mod contract;
pub mod error;
pub mod experiments;
pub mod provenance;
pub mod supervise;
pub mod write;

pub use cli::command::main_with;
pub use cli::{check, faults, robots, simulate};
pub use error::{Error, Result};
pub use experiments::{
    budget, claims, curves, experiment, failures, grids, layouts, maps, progress, radio, readings, refs, scale, seeds,
    sensitivity, set_sweep, settings, stats, sweep, tally,
};
pub use supervise::{launch, run};
pub use write::{
    figures, heatmap, live, mcap, metrics, output, panels, plot, replay, report, routes, rundir, spread, staging,
};
