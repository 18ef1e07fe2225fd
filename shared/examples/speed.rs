use gridswarm::{engine, outcome::RunConfig, params::Situation, policy::Policy, scenario::Scenario};
fn main() {
    let sc = Scenario::builtin("paper").unwrap();
    let world = sc.world();
    let mut rr = 0;
    for n in [1usize, 4, 8, 13] {
        let starts = sc.start_vertices(&world, n).unwrap();
        for policy in [Policy::Repulsive, Policy::Sequential, Policy::Ru] {
            for s in 0..60 {
                let mut cfg = RunConfig::new(policy, s, Situation::One);
                cfg.record_trajectories = false;
                cfg.measure_coverage = false;
                rr += engine::run(&world, &starts, &cfg).robot_rounds;
            }
        }
    }
    println!("{rr} robot-rounds");
}
