//! What makes the in-process engine cheaper must not change a search:
//! faulty, lossy, delayed and duplicating runs must be the same search,
//! frame for frame,
//!
//! - with the receive filter ([`super::Listen`]) as with a radio that
//!   wakes a listening robot for every frame (with fewer wake-ups);
//! - with maps merged by the tiles changed since the sender's last copy
//!   ([`crate::map::Map::merge_changes`]) as with maps merged whole, as a
//!   robot process merges the maps it decodes.

use std::rc::Rc;

use super::{Delivery, Header, Kernel, Listen, Output, Robots, Transmit, WakeCall};
use crate::outcome::RunResult;
use crate::peer::Peer;
use crate::protocol::{Frame, KIND_ACK, KIND_COMMIT};
use crate::vopr;

thread_local! {
    static WORLDS: vopr::Worlds = vopr::Worlds::default();
}

/// Peers as function calls; `unfiltered` widens every filter to all
/// frames, `whole` makes every map sent be merged whole.
struct Plain<'g> {
    peers: Vec<Peer<'g>>,
    out: Output<Frame>,
    unfiltered: bool,
    whole: bool,
}

impl Robots for Plain<'_> {
    type Payload = Rc<Frame>;

    fn wake(&mut self, calls: &mut [WakeCall<Rc<Frame>>], outputs: &mut Vec<Option<Output<Rc<Frame>>>>) {
        outputs.clear();
        for call in calls.iter() {
            let frames = call.frames.iter().map(|d| (d.from, d.at, &*d.payload));
            self.peers[call.robot].wake(call.now, call.tick.as_ref(), frames, &mut self.out);
            let o = &mut self.out;
            let whole = self.whole;
            let send = o.send.drain(..).map(|mut t| {
                if let (true, Frame::Map { map, .. }) = (whole, &mut t.payload) {
                    map.base = None;
                }
                Transmit { payload: Rc::new(t.payload), ready: t.ready, copies: t.copies }
            });
            let listen = if self.unfiltered && o.listen.on { Listen::ALL } else { o.listen };
            let notes = std::mem::take(&mut o.notes);
            outputs.push(Some(Output { send: send.collect(), motor: o.motor, alarm: o.alarm, listen, notes }));
        }
    }

    /// Maps back to their senders, as the in-process engine gives them.
    fn reclaim(&mut self, frames: &mut Vec<Delivery<Rc<Frame>>>) {
        for d in frames.drain(..) {
            if let Ok(Frame::Map { map, from, round, .. }) = Rc::try_unwrap(d.payload) {
                self.peers[from as usize].give_back_map(map, round);
            }
        }
    }
}

fn run(case: &vopr::Case, unfiltered: bool, whole: bool) -> RunResult {
    let (w, starts) = WORLDS.with(|worlds| worlds.of(case));
    let world = &w.1;
    let cfg = &case.config;
    let peers = (0..starts.len())
        .map(|k| Peer::new(&world.grid, cfg.robot_setup(world, k, starts.len()).peer_config()))
        .collect();
    let mut robots = Plain { peers, out: Output::default(), unfiltered, whole };
    Kernel::new(world, &starts, cfg).run(&mut robots)
}

/// The simulation test's cases on `small` with robots that avoid each
/// other (RU robots listen to nothing to filter), those these tests were made on.
fn small_cases(seed: u64) -> impl Iterator<Item = vopr::Case> {
    (0..).map(move |i| vopr::case(seed, i)).filter(|c| c.scenario == "small" && c.config.policy.collision_free())
}

#[test]
fn the_filter_only_removes_wake_ups() {
    let (mut before, mut after) = (0, 0);
    for (i, mut case) in small_cases(7).take(300).enumerate() {
        case.config.record_trajectories = true;
        // Loss in every case, at three rates.
        case.config.radio.loss = [0.0, 0.1, 0.3][i % 3];
        let (mut all, mut filtered) = (run(&case, true, false), run(&case, false, false));
        before += all.protocol.wakes;
        after += filtered.protocol.wakes;
        assert!(filtered.protocol.wakes <= all.protocol.wakes, "case {i}: {}", case.command());
        (all.protocol.wakes, filtered.protocol.wakes) = (0, 0);
        let (a, f) = (serde_json::to_string(&all).unwrap(), serde_json::to_string(&filtered).unwrap());
        assert!(a == f, "case {i} differs with the filter: {}", case.command());
    }
    assert!(after * 10 < before * 9, "the filter saved little: {before} wake-ups to {after}");
}

/// The cases above, with loss and with claims (sequential and escape
/// robots mark the vertices their neighbours chose) dropped as they come.
#[test]
fn merging_changes_only_is_merging_whole_maps() {
    for (i, mut case) in small_cases(11).take(300).enumerate() {
        case.config.record_trajectories = true;
        case.config.radio.loss = [0.0, 0.1, 0.3][i % 3];
        let (whole, changes) = (run(&case, false, true), run(&case, false, false));
        let (w, c) = (serde_json::to_string(&whole).unwrap(), serde_json::to_string(&changes).unwrap());
        assert!(w == c, "case {i} differs when maps are merged by their changes: {}", case.command());
    }
}

#[test]
fn a_held_kind_wakes_only_for_its_exceptions_and_tags_and_only_in_its_round() {
    let mut l = Listen { on: true, round: 5, hold: 1 << KIND_ACK | 1 << KIND_COMMIT, ..Listen::OFF };
    l.except[KIND_ACK as usize] = Listen::bit(3);
    l.tags[KIND_COMMIT as usize] = 1 << 9;
    let h = |kind, round| Some(Header { kind, round, tag: 1 << 2 });
    assert!(!l.wakes(1, h(KIND_ACK, 5)));
    assert!(l.wakes(3, h(KIND_ACK, 5)), "an exception");
    assert!(l.wakes(67, h(KIND_ACK, 5)), "shares robot 3's bit: woken needlessly, never held wrongly");
    assert!(!l.wakes(3, h(KIND_COMMIT, 5)), "exceptions are per kind");
    assert!(l.wakes(1, h(KIND_ACK, 4)), "another round's frame");
    assert!(l.wakes(1, h(0, 5)), "a kind not held");
    assert!(l.wakes(1, h(200, 5)), "an unknown kind");
    assert!(l.wakes(1, None), "no header to read");
    assert!(l.wakes(1, Some(Header { kind: KIND_COMMIT, round: 5, tag: 1 << 9 })), "a tag it wakes for");
    assert!(!l.wakes(1, Some(Header { kind: KIND_ACK, round: 5, tag: 1 << 9 })), "tags are per kind");
    assert!(!Listen::OFF.wakes(1, h(0, 5)) && !Listen::OFF.wakes(1, None));
    assert!(Listen::ALL.wakes(1, h(KIND_ACK, 0)));
}
