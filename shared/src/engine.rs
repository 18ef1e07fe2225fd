//! The in-process engine: every robot's radio protocol ([`crate::peer`])
//! and decision core in one thread, woken by the simulated world
//! ([`crate::sim`]) through function calls. Frames travel as shared values,
//! never encoded. The world-server runs the same world with robots in
//! other processes, so the two engines agree run for run.

use std::rc::Rc;

use crate::grid::VertexId;
use crate::lfp::{self, LfpParams};
use crate::outcome::{RunConfig, RunResult};
use crate::peer::Peer;
use crate::policy::Policy;
use crate::protocol::Frame;
use crate::setup::RobotSetup;
use crate::sim::{Kernel, Output, Robots, Transmit, WakeCall};
use crate::world::World;

/// Side of a raster cell for the detected fraction, in units of `a`.
pub const RASTER_CELL: f64 = 0.1;

/// Runs one search with robots starting at `starts` (robot `k` at
/// `starts[k]`), LFP with its default constants.
pub fn run(world: &World, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
    run_with_lfp(world, starts, cfg, &LfpParams::default())
}

/// [`run`] with LFP's constants given (they matter only to LFP).
pub fn run_with_lfp(world: &World, starts: &[VertexId], cfg: &RunConfig, lfp: &LfpParams) -> RunResult {
    match cfg.policy {
        Policy::Lfp => {
            let mut times = Vec::new();
            let mut r = lfp::run_timed(world, starts, cfg, lfp, &mut times);
            r.round_end_times_s = times;
            r
        }
        Policy::Oracle => crate::oracle::run(world, starts, cfg),
        _ => run_grid(world, starts, cfg),
    }
}

fn run_grid(world: &World, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
    let peers = (0..starts.len()).map(|k| Peer::new(&world.grid, RobotSetup::new(world, cfg, k).peer_config())).collect();
    let mut local = Local { peers, out: Output::default() };
    Kernel::new(world, starts, cfg).run(&mut local)
}

/// Robots as function calls.
struct Local<'g> {
    peers: Vec<Peer<'g>>,
    out: Output<Frame>,
}

impl Robots for Local<'_> {
    type Payload = Rc<Frame>;

    fn wake(&mut self, calls: &mut [WakeCall<Rc<Frame>>], outputs: &mut Vec<Option<Output<Rc<Frame>>>>) {
        for call in calls.iter() {
            let frames = call.frames.iter().map(|d| (d.from, &*d.payload));
            self.peers[call.robot].wake(call.now, call.tick.as_ref(), frames, &mut self.out);
            let o = &mut self.out;
            outputs.push(Some(Output {
                send: o.send.drain(..).map(|t| Transmit { payload: Rc::new(t.payload), ready: t.ready, copies: t.copies }).collect(),
                motor: o.motor,
                alarm: o.alarm,
                listen: o.listen,
                notes: std::mem::take(&mut o.notes),
            }));
        }
    }
}
