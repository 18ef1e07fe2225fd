//! The command line's own work: the fault and radio flags shared by
//! `simulate` and `run`, robot-count lists, and the commands that are one
//! in-process call (`simulate`, `check`, `export-map`), and `credentials`
//! and `setup` (the files an agent started by hand needs).
//! `main.rs` parses and dispatches.

pub mod agents;
pub mod check;
pub mod credentials;
pub mod export;
pub mod faults;
pub mod robots;
pub mod setup;
pub mod simulate;
pub mod transport;
pub mod view;
