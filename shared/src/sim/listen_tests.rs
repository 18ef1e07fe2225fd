//! The receive filter ([`super::Listen`]) against a radio that wakes a
//! listening robot for every frame: faulty, lossy, delayed and duplicating
//! runs must be the same search, frame for frame, with fewer wake-ups.

use std::rc::Rc;

use super::{Delivery, Header, Kernel, Listen, Output, Robots, Transmit, WakeCall};
use crate::outcome::RunResult;
use crate::peer::Peer;
use crate::protocol::{Frame, KIND_ACK, KIND_COMMIT};
use crate::scenario::Scenario;
use crate::setup::RobotSetup;
use crate::vopr;

/// Peers as function calls; `unfiltered` widens every filter to all frames.
struct Plain<'g> {
    peers: Vec<Peer<'g>>,
    out: Output<Frame>,
    unfiltered: bool,
}

impl Robots for Plain<'_> {
    type Payload = Rc<Frame>;

    fn wake(&mut self, calls: &mut [WakeCall<Rc<Frame>>], outputs: &mut Vec<Option<Output<Rc<Frame>>>>) {
        outputs.clear();
        for call in calls.iter() {
            let frames = call.frames.iter().map(|d| (d.from, &*d.payload));
            self.peers[call.robot].wake(call.now, call.tick.as_ref(), frames, &mut self.out);
            let o = &mut self.out;
            let send =
                o.send.drain(..).map(|t| Transmit { payload: Rc::new(t.payload), ready: t.ready, copies: t.copies });
            let listen = if self.unfiltered && o.listen.on { Listen::ALL } else { o.listen };
            let notes = std::mem::take(&mut o.notes);
            outputs.push(Some(Output { send: send.collect(), motor: o.motor, alarm: o.alarm, listen, notes }));
        }
    }

    fn reclaim(&mut self, _frames: &mut Vec<Delivery<Rc<Frame>>>) {}
}

fn run(case: &vopr::Case, unfiltered: bool) -> RunResult {
    let sc = Scenario::builtin(vopr::SCENARIO).unwrap();
    let world = sc.world();
    let starts = sc.start_vertices(&world, case.robots).unwrap();
    let cfg = &case.config;
    let peers =
        (0..starts.len()).map(|k| Peer::new(&world.grid, RobotSetup::new(&world, cfg, k).peer_config())).collect();
    let mut robots = Plain { peers, out: Output::default(), unfiltered };
    Kernel::new(&world, &starts, cfg).run(&mut robots)
}

#[test]
fn the_filter_only_removes_wake_ups() {
    let (mut before, mut after) = (0, 0);
    for i in 0..300 {
        let mut case = vopr::case(7, i);
        case.config.record_trajectories = true;
        // Loss too, which the simulation test leaves out.
        case.config.radio.loss = [0.0, 0.1, 0.3][i as usize % 3];
        let (mut all, mut filtered) = (run(&case, true), run(&case, false));
        before += all.protocol.wakes;
        after += filtered.protocol.wakes;
        assert!(filtered.protocol.wakes <= all.protocol.wakes, "case {i}: {}", case.command());
        (all.protocol.wakes, filtered.protocol.wakes) = (0, 0);
        let (a, f) = (serde_json::to_string(&all).unwrap(), serde_json::to_string(&filtered).unwrap());
        assert!(a == f, "case {i} differs with the filter: {}", case.command());
    }
    assert!(after * 10 < before * 9, "the filter saved little: {before} wake-ups to {after}");
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
