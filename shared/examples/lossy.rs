use gridswarm::{engine, outcome::RunConfig, params::Situation, policy::Policy, scenario::Scenario, sim::Radio};
fn main() {
    let mut sc = Scenario::builtin("paper").unwrap();
    for r in [0u32, 1, 2] {
        sc.params.retries = r;
        let world = sc.world();
        let starts = world_starts(&sc, &world, 13);
        for p in [0.0, 0.05, 0.1, 0.2, 0.3] {
            let (mut col, mut moves, mut comp, mut time, mut unsure, mut fs) = (0u64, 0u64, 0, 0.0, 0u64, 0u64);
            let runs = 100;
            for s in 0..runs {
                let mut cfg = RunConfig::new(Policy::Repulsive, s, Situation::One);
                cfg.record_trajectories = false;
                cfg.measure_coverage = false;
                cfg.max_rounds = 3000;
                cfg.radio = Radio { loss: p, ..Radio::default() };
                let res = engine::run(&world, &starts, &cfg);
                col += res.collisions as u64;
                moves += res.protocol.moves;
                comp += res.complete as u32;
                time += res.search_time_s;
                unsure += res.protocol.unsure;
                fs += res.protocol.false_suspicions;
            }
            println!("R={r} P={p}: collisions {col} per 1e6 moves {:.1}, complete {comp}/{runs}, mean time {:.0} s, unsure {unsure}, false suspicions {fs}", col as f64 * 1e6 / moves as f64, time / runs as f64);
        }
    }
}
fn world_starts(sc: &Scenario, w: &gridswarm::world::World, n: usize) -> Vec<u32> { sc.start_vertices(w, n).unwrap() }
