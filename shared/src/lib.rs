//! gridswarm: decentralized multi-robot search on a grid (Yang, CCC 2017).
//!
//! Layers, lowest first: [`geometry`] and [`lattice`] know nothing of robots;
//! [`grid`] is the frame robots share; [`world`] is the ground truth only
//! the simulated world holds; [`robot`] is the decision core and [`peer`]
//! the robot's radio protocol on top of it, both with no I/O; [`sim`] is
//! the world (clock, radio medium, bodies, faults); [`engine`] runs robots
//! in-process. See ARCHITECTURE.md.

pub mod agreement;
pub mod assumptions;
pub mod bitset;
pub mod choice;
pub mod engine;
pub mod geometry;
pub mod grid;
/// The distributed engine's shared pieces (iceoryx2 config, names, cleanup).
#[cfg(feature = "ipc")]
pub mod ipc;
pub mod lattice;
pub mod lfp;
pub mod map;
pub mod near;
#[cfg(feature = "zenoh")]
pub mod net;
#[cfg(feature = "ipc")]
pub mod nofile;
pub mod oracle;
pub mod outcome;
pub mod params;
pub mod peer;
pub mod policy;
pub mod protocol;
pub mod referee;
pub mod rng;
pub mod robot;
pub mod scenario;
pub mod setup;
pub mod sim;
pub mod transport;
pub mod vopr;
pub mod wire;
pub mod world;
