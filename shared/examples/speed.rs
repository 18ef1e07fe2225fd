use gridswarm::engine;
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use std::time::Instant;

fn main() {
    let sc = Scenario::builtin("paper").unwrap();
    let world = sc.world();
    for policy in [Policy::Repulsive, Policy::Sequential, Policy::Ru] {
        for n in [1usize, 4, 13] {
            let starts = sc.start_vertices(&world, n).unwrap();
            let t = Instant::now();
            let (mut rr, mut rounds, mut time, mut complete, mut wakes, mut frames) = (0u64, 0u64, 0.0, 0, 0u64, 0u64);
            let runs = 200;
            for s in 0..runs {
                let mut cfg = RunConfig::new(policy, s, Situation::One);
                cfg.record_trajectories = false;
                cfg.measure_coverage = false;
                let r = engine::run(&world, &starts, &cfg);
                rr += r.robot_rounds;
                rounds += r.rounds as u64;
                time += r.search_time_s;
                complete += r.complete as u32;
                wakes += r.protocol.wakes;
                frames += r.protocol.frames;
                if policy != Policy::Ru { assert_eq!(r.collisions, 0, "{policy} {n} {s}"); }
            }
            let el = t.elapsed().as_secs_f64();
            println!("{policy} n={n}: {:.3} s, {:.2} M robot-rounds/s, mean rounds {:.1}, mean time {:.0} s, complete {complete}/{runs}, wakes/robot-round {:.2}, frames/robot-round {:.2}",
                el, rr as f64 / el / 1e6, rounds as f64 / runs as f64, time / runs as f64, wakes as f64 / rr as f64, frames as f64 / rr as f64);
        }
    }
}
