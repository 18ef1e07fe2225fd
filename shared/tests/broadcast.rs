//! Step 8's information model (issue 36, item 1): under the controller's
//! relay (the default) a search ends within a slot's exchange of its last
//! find, for every grid rule and RU as for LFP, radio faults included; under
//! the radio flood alone it may end hundreds of seconds later, which is why
//! the comparison of Fig. 7 uses the relay.

use gridswarm::engine;
use gridswarm::lfp::LfpParams;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::params::{Broadcast, Situation};
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm::sim::Radio;

const SEEDS: u64 = 6;

/// Search end minus last find, for the complete runs of `policy` on
/// `paper` with `robots` robots under `broadcast` and `radio`.
fn lags(policy: Policy, robots: usize, broadcast: Broadcast, radio: Radio) -> Vec<f64> {
    let mut sc = Scenario::builtin("paper").unwrap();
    sc.params.broadcast = broadcast;
    let world = sc.world();
    let starts = sc.start_vertices(&world, robots).unwrap();
    (0..SEEDS)
        .map(|seed| {
            let mut cfg = RunConfig::new(policy, seed, Situation::One);
            cfg.record_trajectories = false;
            cfg.measure_coverage = false;
            cfg.radio = radio;
            cfg.max_rounds = 5_000;
            let r = engine::run_with_lfp(&world, &starts, &cfg, &LfpParams::default());
            assert!(r.complete, "{policy} seed {seed} under {broadcast:?}: {}", r.protocol.ended_by);
            lag(&r)
        })
        .collect()
}

fn lag(r: &RunResult) -> f64 {
    assert_eq!(r.metrics.targets_s.len(), r.targets_total);
    r.search_time_s - r.metrics.targets_s.last().copied().unwrap()
}

#[test]
fn under_the_relay_every_algorithm_ends_at_its_last_find() {
    let p = gridswarm::params::Params::default();
    // A grid robot tests its stop at its exchange's end; LFP's at once, or
    // two hops later if another robot found a target of the same round.
    for policy in [Policy::Ru, Policy::Sequential, Policy::Repulsive, Policy::Lfp] {
        for l in lags(policy, 5, Broadcast::Controller, Radio::default()) {
            assert!((0.0..=p.t_exchange + 2.0 * p.t_hop + 1e-9).contains(&l), "{policy}: lag {l} s");
        }
    }
}

#[test]
fn the_relay_reaches_every_robot_through_loss_and_delay() {
    let radio = Radio { loss: 0.2, delay: 30_000, jitter: 10_000, dup: 0.1 };
    // Lost relays are not sent again: a robot may learn a target only from
    // a later flood, or find it itself, so the lag is bounded loosely, not
    // to the exchange. It must still be far below the flood's alone.
    let relay: Vec<f64> = lags(Policy::Repulsive, 5, Broadcast::Controller, radio);
    assert!(relay.iter().all(|&l| l >= 0.0), "{relay:?}");
    let mean = relay.iter().sum::<f64>() / relay.len() as f64;
    assert!(mean < 10.0, "mean lag {mean} s under loss: {relay:?}");
}

#[test]
fn the_flood_alone_ends_grid_searches_late() {
    // The reading before issue 36: few robots are ever in range of each
    // other on `paper`, so the robot that finds the last target rarely
    // knows the others. The difference is what the switch is for.
    let late = lags(Policy::Sequential, 5, Broadcast::Flood, Radio::default());
    assert!(late.iter().filter(|&&l| l > 1.0).count() >= 2, "{late:?}");
}
