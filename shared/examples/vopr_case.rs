//! Runs one case of the simulation test and prints its outcome:
//! `GRIDSWARM_TRACE=1 cargo run --release --example vopr_case -- SEED INDEX`.
use gridswarm::{engine, vopr};
fn main() {
    let a: Vec<u64> = std::env::args().skip(1).map(|s| s.parse().unwrap()).collect();
    let case = vopr::case(a[0], a[1]);
    let worlds = vopr::Worlds::default();
    let (w, starts) = worlds.of(&case);
    let world = &w.1;
    println!("{}", case.command());
    println!("{:?}", case.config);
    let mut cfg = case.config.clone();
    cfg.record_trajectories = true;
    let r = engine::run(&world, &starts, &cfg);
    for (k, t) in r.trajectories.iter().enumerate() {
        let last: Vec<String> =
            t.iter().rev().take(12).map(|p| format!("{:?}", p.vertex.map(|c| (c.i, c.j)).unwrap())).collect();
        println!("robot {k} last positions (newest first): {}", last.join(" "));
    }
    let va = world.reachable_from(&starts);
    let unvisited: Vec<String> = (0..world.grid.len())
        .filter(|&v| va[v])
        .map(|v| world.grid.coord(v as u32))
        .map(|c| format!("({},{})", c.i, c.j))
        .collect();
    println!("Va: {}", unvisited.join(" "));
    println!(
        "rounds {} ended {} collisions {} {:?}",
        r.rounds,
        r.protocol.ended_by,
        r.collisions,
        vopr::check(&case, &r, 1)
    );
    println!("failures {:?}", r.protocol.failures);
}
