//! gridswarm: decentralized multi-robot search on a grid (Yang, CCC 2017).
//!
//! Layers, lowest first: [`geometry`] and [`lattice`] know nothing of robots;
//! [`grid`] is the frame robots share; [`world`] is the ground truth only
//! the simulated world holds; [`robot`] is the decision core and [`peer`]
//! the robot's radio protocol on top of it, both with no I/O; [`sim`] is
//! the world (clock, radio medium, bodies, faults); [`engine`] runs robots
//! in-process. See ARCHITECTURE.md.
//!
//! The robot's modules are the crate `gridswarm_robot`, which knows no
//! world; they are re-exported here under their old names.

pub use gridswarm_robot::{
    agreement, bitset, choice, geometry, grid, lattice, map, params, peer, policy, protocol, rng, robot, setup, spot,
    wire,
};

/// The transports are the crate `gridswarm_transport` (feature `ipc`),
/// re-exported under their old names; the run's files, which speak of the
/// world, are [`run_file`]'s.
#[cfg(feature = "ipc")]
pub mod ipc {
    pub use crate::run_file::{RunFile, RunReport};
    pub use gridswarm_transport::ipc::*;
}
#[cfg(feature = "ipc")]
pub use gridswarm_transport as transport;
#[cfg(feature = "zenoh")]
pub use gridswarm_transport::net;
#[cfg(feature = "ipc")]
pub use gridswarm_transport::nofile;

pub mod assumptions;
pub mod bound;
pub mod bounds;
pub mod engine;
pub mod lfp;
pub mod near;
pub mod oracle;
pub mod outcome;
pub mod referee;
pub mod run_file;
pub mod scenario;
pub mod sim;
pub mod vopr;
pub mod world;
