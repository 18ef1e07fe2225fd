//! LFP: Levy flight with an artificial potential field (Sutantyo et al.
//! 2010), the continuous-motion baseline of Fig. 7. HELPER-OWNED: being written.

use serde::{Deserialize, Serialize};

use crate::grid::VertexId;
use crate::outcome::{RunConfig, RunResult};
use crate::world::World;

/// LFP's constants. The paper gives none; these defaults are the project's
/// documented choice and every one can be set in a scenario's `[lfp]` table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LfpParams {
    /// Levy exponent for Mantegna's method.
    pub beta: f64,
    /// Step lengths are `scale * a * |levy|`, clamped to `[a, max_step * a]`.
    pub scale: f64,
    pub max_step: f64,
    /// Standard deviation of the turn angle between flights (rad).
    pub turn_sigma: f64,
    /// Gain of the repulsion from other robots within `r_c`.
    pub k_robot: f64,
    /// Gain of the repulsion from obstacles and boundary within `r_so`.
    pub k_obstacle: f64,
}

impl Default for LfpParams {
    fn default() -> Self {
        LfpParams { beta: 1.5, scale: 1.0, max_step: 20.0, turn_sigma: 0.5, k_robot: 1.0, k_obstacle: 1.0 }
    }
}

pub fn run(world: &World, starts: &[VertexId], cfg: &RunConfig, lfp: &LfpParams) -> RunResult {
    let _ = (world, starts, cfg, lfp);
    unimplemented!("lfp being written")
}
