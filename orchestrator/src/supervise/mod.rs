//! Process supervision for distributed runs: spawning the world-server and
//! one robot-agent per robot so that none outlives the run, following the
//! world, injecting faults at its pauses, and removing every file of the
//! run (`run`), on the plumbing of `launch`.

pub mod launch;
pub mod run;
