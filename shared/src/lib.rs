//! gridswarm: decentralized multi-robot search on a grid (Yang, CCC 2017).
//!
//! Layers, lowest first: [`geometry`] and [`lattice`] know nothing of robots;
//! [`grid`] is the frame robots share; [`world`] is the ground truth only
//! the simulated world holds; [`robot`] is the decision core and [`peer`]
//! the robot's radio protocol on top of it, both with no I/O; [`sim`] is
//! the world (clock, radio medium, bodies, faults); [`engine`] runs robots
//! in-process. See ARCHITECTURE.md.

pub mod bitset;
pub mod geometry;
pub mod near;
pub mod grid;
pub mod lattice;
pub mod params;
pub mod world;
pub mod engine;
pub mod outcome;
pub mod policy;
pub mod choice;
pub mod scenario;
pub mod lfp;
pub mod oracle;
pub mod map;
pub mod rng;
pub mod robot;
pub mod peer;
pub mod sim;
pub mod setup;
pub mod referee;
pub mod protocol;
pub mod wire;
pub mod transport;
pub mod assumptions;
pub mod vopr;
/// The distributed engine's shared pieces (iceoryx2 config, names, cleanup).
#[cfg(feature = "ipc")]
pub mod ipc;
#[cfg(feature = "ipc")]
pub mod nofile;
#[cfg(feature = "zenoh")]
pub mod net;
