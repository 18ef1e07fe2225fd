//! The command line's own work: the fault and radio flags shared by
//! `simulate` and `run`, robot-count lists, and the commands that are one
//! in-process call (`simulate`, `check`, `export-map`, `map-setup`), and `credentials`
//! and `setup` (the files an agent started by hand needs).
//! `command.rs` is the command line itself: it parses and dispatches
//! (`main.rs` only calls it).

pub mod agents;
pub mod check;
pub mod command;
pub mod credentials;
pub mod export;
pub mod faults;
pub mod map_setup;
pub mod robots;
pub mod setup;
pub mod simulate;
pub mod transport;
pub mod view;
