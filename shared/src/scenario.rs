//! Scenario files (TOML) and the built-in scenarios.
//!
//! HELPER-OWNED: the parser, errors and built-ins are being written; the
//! public shape below is the contract the rest of the code uses.

use crate::geometry::{Point, Polygon, Shape};
use crate::grid::VertexId;
use crate::lattice::LatticeKind;
use crate::params::{Params, Situation};
use crate::world::World;

/// Where the robots start.
#[derive(Clone, Debug, PartialEq)]
pub enum Starts {
    /// Neighbouring accessible vertices along the area's border, beginning
    /// with the border vertex nearest to `from` (Assumption 2.2).
    Border { from: Point },
    /// Given points, each snapped to its nearest lattice vertex.
    Points(Vec<Point>),
}

/// A search problem: everything needed to build a [`World`] and place robots.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    pub name: String,
    pub area: Polygon,
    pub obstacles: Vec<Shape>,
    pub targets: Vec<Point>,
    pub starts: Starts,
    /// Robot count used when the command line does not give one.
    pub robots: usize,
    pub params: Params,
    pub grid: LatticeKind,
    pub situation: Situation,
}

impl Scenario {
    /// The ground truth of this scenario on its own grid.
    pub fn world(&self) -> World {
        World::new(self.area.clone(), self.obstacles.clone(), self.targets.clone(), self.params, self.grid)
    }
}

#[allow(unused)]
fn _contract(_: &World, _: usize) -> Option<Vec<VertexId>> {
    None
}
