//! gridswarm's robot: everything one robot runs and holds, and nothing of
//! the world it runs in. The crate has no dependency on the world, the
//! scenarios, the referee or the engines, so the compiler keeps "a robot
//! knows only what it sensed or heard": what it knows comes in through
//! [`io`] (readings and frames), from its [`setup`] (what it holds before
//! it starts) and from its own [`map`].
//!
//! Layers, lowest first: [`geometry`] and [`lattice`] know nothing of
//! robots; [`grid`] is the frame robots share; [`map`] a robot's explored
//! map; [`robot`] the decision core, whose one varying decision is a
//! [`choice`] rule; [`peer`] the robot's radio protocol on top of it, its
//! frames in [`protocol`]; [`wire`] the messages between a robot process
//! and the world. See ARCHITECTURE.md.

pub mod agreement;
pub mod bitset;
pub mod choice;
pub mod geometry;
pub mod grid;
pub mod io;
pub mod lattice;
pub mod map;
pub mod params;
pub mod peer;
pub mod policy;
pub mod protocol;
pub mod rng;
pub mod robot;
pub mod setup;
pub mod spot;
pub mod trail;
pub mod wire;
