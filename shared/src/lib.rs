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
    agreement, bitset, choice, geometry, grid, lattice, map, params, peer, policy, protocol, rng, robot, setup, wire,
};

pub mod assumptions;
pub mod engine;
/// The distributed engine's shared pieces (iceoryx2 config, names, cleanup).
#[cfg(feature = "ipc")]
pub mod ipc;
pub mod lfp;
pub mod near;
#[cfg(feature = "zenoh")]
pub mod net;
#[cfg(feature = "ipc")]
pub mod nofile;
pub mod oracle;
pub mod outcome;
pub mod referee;
pub mod scenario;
pub mod sim;
pub mod transport;
pub mod vopr;
pub mod world;
