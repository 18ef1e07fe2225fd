//! Writers: a run's directory (summary, trajectories, world, rounds,
//! replay page), the figures and tables experiments print and draw, and
//! the report pages. They own files; they never decide anything.

pub mod figures;
pub mod heatmap;
pub mod live;
pub mod mcap;
pub mod metrics;
pub mod output;
pub mod palette;
pub mod panels;
pub mod plot;
pub mod replay;
pub mod report;
pub mod routes;
pub mod rundir;
pub mod spread;
pub mod staging;
