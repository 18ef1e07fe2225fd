//! The in-process engine: every robot's radio protocol ([`crate::peer`])
//! and decision core in one thread, woken by the simulated world
//! ([`crate::sim`]) through function calls. Frames travel as shared values,
//! never encoded. The world-server runs the same world with robots in
//! other processes, so the two engines agree run for run.

use std::rc::Rc;
use std::sync::OnceLock;

use crate::grid::VertexId;
use crate::lfp::{self, LfpParams};
use crate::map::tiles::SharedMasks;
use crate::outcome::{RunConfig, RunResult};
use crate::peer::Peer;
use crate::policy::Policy;
use crate::protocol::Frame;
use crate::sim::watch::Watch;
use crate::sim::{Delivery, Kernel, Output, Robots, Transmit, WakeCall};
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
    Prepared::new(world).run(starts, cfg, lfp)
}

/// A world made ready for many runs: what an algorithm precomputes of it
/// (LFP's obstacle index, the oracle's distance tables) is built on first
/// use and kept, so a sweep of thousands of runs on one world builds it
/// once. Shared across threads.
pub struct Prepared<'w> {
    world: &'w World,
    lfp: OnceLock<lfp::LfpWorld<'w>>,
    oracle: OnceLock<crate::oracle::OracleWorld<'w>>,
}

impl<'w> Prepared<'w> {
    pub fn new(world: &'w World) -> Self {
        Prepared { world, lfp: OnceLock::new(), oracle: OnceLock::new() }
    }

    pub fn world(&self) -> &'w World {
        self.world
    }

    /// One search, as [`run_with_lfp`].
    pub fn run(&self, starts: &[VertexId], cfg: &RunConfig, lfp: &LfpParams) -> RunResult {
        match cfg.policy {
            Policy::Lfp => {
                let lw = self.lfp.get_or_init(|| lfp::LfpWorld::new(self.world));
                lfp::run_prepared(lw, starts, cfg, lfp)
            }
            Policy::Oracle => {
                let ow = self.oracle.get_or_init(|| crate::oracle::OracleWorld::new(self.world));
                crate::oracle::run_prepared(ow, starts, cfg)
            }
            _ => run_grid(self.world, starts, cfg),
        }
    }
}

fn run_grid(world: &World, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
    let _masks = SharedMasks::new(world.grid.len());
    Kernel::new(world, starts, cfg).run(&mut Local::new(world, starts, cfg))
}

/// One search of a grid policy shown to `watch` as it goes ([`crate::sim::watch`]):
/// the same search as [`run`]'s.
pub fn run_grid_watched(
    world: &World,
    starts: &[VertexId],
    cfg: &RunConfig,
    watch: &mut dyn Watch<Rc<Frame>>,
) -> RunResult {
    let _masks = SharedMasks::new(world.grid.len());
    Kernel::new(world, starts, cfg).watched(watch).run(&mut Local::new(world, starts, cfg))
}

/// Robots as function calls.
struct Local<'g> {
    peers: Vec<Peer<'g>>,
    out: Output<Frame>,
    /// Frames every receiver has read, their allocations reused for the
    /// next frames sent (about three a robot a slot).
    frames: Vec<Rc<Frame>>,
}

impl<'g> Local<'g> {
    /// Every robot's map reads its edge masks from one table, made by the
    /// caller ([`SharedMasks`]): they are physics.
    fn new(world: &'g World, starts: &[VertexId], cfg: &RunConfig) -> Self {
        let peers = (0..starts.len())
            .map(|k| Peer::new(&world.grid, cfg.robot_setup(world, k, starts.len()).peer_config()))
            .collect();
        Local { peers, out: Output::default(), frames: Vec::new() }
    }
}

impl Robots for Local<'_> {
    type Payload = Rc<Frame>;

    fn wake(&mut self, calls: &mut [WakeCall<Rc<Frame>>], outputs: &mut Vec<Option<Output<Rc<Frame>>>>) {
        outputs.resize_with(calls.len(), || None);
        for (call, slot) in calls.iter().zip(outputs.iter_mut()) {
            let peer = &mut self.peers[call.robot];
            let frames = call.frames.iter().map(|d| (d.from, d.at, &*d.payload));
            peer.wake(call.now, call.tick.as_ref(), frames, &mut self.out);
            let (o, into) = (&mut self.out, slot.get_or_insert_with(Output::default));
            into.send.clear();
            for t in o.send.drain(..) {
                let payload = match self.frames.pop() {
                    Some(mut rc) => {
                        *Rc::get_mut(&mut rc).expect("kept frames are read by all") = t.payload;
                        rc
                    }
                    None => Rc::new(t.payload),
                };
                into.send.push(Transmit { payload, ready: t.ready, copies: t.copies });
            }
            into.notes.clear();
            into.notes.append(&mut o.notes);
            (into.motor, into.alarm, into.listen) = (o.motor, o.alarm, o.listen);
        }
    }

    fn reclaim(&mut self, frames: &mut Vec<Delivery<Rc<Frame>>>) {
        let keep = 4 * self.peers.len();
        for d in frames.drain(..) {
            // The last reader of a frame gives it back, and a map frame its map.
            let mut rc = d.payload;
            let Some(frame) = Rc::get_mut(&mut rc) else { continue };
            if let Frame::Map { map, from, round, .. } = frame {
                // To its sender, whose next copy need only take what changed
                // since: a map a robot a slot, without allocating.
                if let Some(peer) = self.peers.get_mut(*from as usize) {
                    peer.give_back_map(std::mem::take(map), *round);
                }
            }
            if self.frames.len() < keep {
                self.frames.push(rc);
            }
        }
    }
}
