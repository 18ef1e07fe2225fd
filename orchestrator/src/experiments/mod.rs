//! Experiments: many runs, their statistics and their claims. The Fig. 7
//! sweep (`experiment`), `failures`, `radio`, `scale`, the lattice
//! comparison (`grids`), the paper's claims, and the pieces they share:
//! running jobs on either engine (`sweep`), showing that they run (`progress`), how long a run may take (`budget`), where runs start (`layouts`), reading a run's figures
//! (`tally`), statistics and coverage against time (`curves`), seeds, the maps a sweep runs on (`maps`), and how
//! much a sweep depends on the paper's readings (`sensitivity`), the
//! references cells are measured against (`refs`), and the
//! claims re-evaluated over a grid of those readings (`readings`), and the
//! sweep over a grid of `--set` scenario values (`settings`, `set_sweep`).

pub mod budget;
pub mod claims;
pub mod curves;
pub mod experiment;
pub mod failures;
pub mod grids;
pub mod layouts;
pub mod maps;
pub mod progress;
pub mod radio;
pub mod readings;
pub mod refs;
pub mod scale;
pub mod seeds;
pub mod sensitivity;
pub mod set_sweep;
pub mod settings;
pub mod stats;
pub mod sweep;
pub mod tally;
