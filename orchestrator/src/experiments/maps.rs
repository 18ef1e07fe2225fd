//! The maps a Fig. 7 sweep runs on: the one scenario named, or with
//! `--maps K` the K random maps `random:SEED+k,options` (k = 0..K) derived
//! from the `--scenario random:SEED,options` given, so map `k` can be
//! rerun, checked or simulated alone by its name. A named or file scenario
//! is one map; asking for several of it is an error, not K copies.

use std::fmt::Write as _;
use std::time::Instant;

use gridswarm::scenario::random::{self, Spec};
use gridswarm::scenario::Scenario;
use serde::Serialize;

use crate::contract;
use crate::error::{Error, Result};
use crate::stats::CellStats;

/// One map of a sweep and what making it cost.
#[derive(Clone, Debug)]
pub struct Map {
    pub scenario: Scenario,
    /// Draws the generator needed (1 for a named or file scenario).
    pub attempts: u64,
    /// Wall time to make (generate, or load and parse) the map, ms.
    pub make_ms: f64,
}

/// What `maps.csv` and `summary.json` say of each map.
#[derive(Clone, Debug, Serialize)]
pub struct MapRow {
    pub map: usize,
    pub scenario: String,
    pub attempts: u64,
    pub make_ms: f64,
    pub obstacles: usize,
    pub obstacle_share: f64,
    pub accessible_vertices: usize,
}

/// The maps of a sweep: `scenario` alone without `maps`, else `maps`
/// random maps from it.
pub fn resolve(scenario: &str, maps: Option<u32>) -> Result<Vec<Map>> {
    let Some(k) = maps else {
        let started = Instant::now();
        let scenario = contract::load_scenario(scenario)?;
        return Ok(vec![Map { scenario, attempts: 1, make_ms: started.elapsed().as_secs_f64() * 1e3 }]);
    };
    if !random::is_random(scenario) {
        return Err(Error::Usage(format!(
            "--maps needs a random scenario, e.g. --scenario random:1 or random:1,size=30x20 \
             (`{scenario}` is one fixed map; map k is random:SEED+k with the same options)"
        )));
    }
    let spec = Spec::parse(scenario).map_err(|e| Error::Scenario(e.to_string()))?;
    let last = spec.seed.checked_add(u64::from(k) - 1).ok_or_else(|| {
        Error::Input(format!("--maps {k} from seed {}: the last map's seed would pass 2^64 - 1", spec.seed))
    })?;
    (spec.seed..=last)
        .map(|seed| {
            let started = Instant::now();
            let g = random::generate(&spec.with_seed(seed)).map_err(|e| Error::Scenario(e.to_string()))?;
            Ok(Map { scenario: g.scenario, attempts: g.attempts, make_ms: started.elapsed().as_secs_f64() * 1e3 })
        })
        .collect()
}

/// The rows of `maps.csv`.
pub fn rows(maps: &[Map]) -> Vec<MapRow> {
    maps.iter()
        .enumerate()
        .map(|(k, m)| {
            let world = m.scenario.world();
            MapRow {
                map: k,
                scenario: m.scenario.name.clone(),
                attempts: m.attempts,
                make_ms: m.make_ms,
                obstacles: m.scenario.obstacles.len(),
                obstacle_share: random::obstacle_area(&m.scenario) / m.scenario.area.signed_area().abs(),
                accessible_vertices: world.accessible_vertices().count(),
            }
        })
        .collect()
}

/// `maps.csv`: one row per map, to rerun or inspect any of them.
pub fn csv(rows: &[MapRow]) -> String {
    let mut s = String::from("map,scenario,attempts,make_ms,obstacles,obstacle_share,accessible_vertices\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},\"{}\",{},{:.3},{},{:.4},{}",
            r.map, r.scenario, r.attempts, r.make_ms, r.obstacles, r.obstacle_share, r.accessible_vertices
        );
    }
    s
}

/// One line for the terminal: how many maps, their names, what they cost.
pub fn summary_line(maps: &[Map]) -> String {
    let total: f64 = maps.iter().map(|m| m.make_ms).sum();
    let attempts: u64 = maps.iter().map(|m| m.attempts).sum();
    let (first, last) = (&maps[0].scenario.name, &maps[maps.len() - 1].scenario.name);
    format!(
        "maps: {} ({first} .. {last}), generated in {total:.1} ms ({:.2} ms and {:.2} draws per map)\n",
        maps.len(),
        total / maps.len() as f64,
        attempts as f64 / maps.len() as f64
    )
}

/// The spread over maps of one (algorithm, robots) cell: the per-map mean
/// search times' least, median and greatest, and on which maps.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Spread {
    pub algorithm: gridswarm::policy::Policy,
    pub robots: usize,
    /// Maps with at least one completed run (the others have no mean).
    pub maps: usize,
    pub min_s: Option<f64>,
    pub median_s: Option<f64>,
    pub max_s: Option<f64>,
    pub min_map: Option<usize>,
    pub max_map: Option<usize>,
}

/// The spread of every cell; `per_map[m]` holds map `m`'s cells, all in
/// the same cell order.
pub fn spreads(per_map: &[Vec<CellStats>]) -> Vec<Spread> {
    let Some(first) = per_map.first() else { return Vec::new() };
    (0..first.len())
        .map(|c| {
            let means: Vec<(usize, f64)> = per_map
                .iter()
                .enumerate()
                .filter_map(|(m, cells)| cells[c].mean_search_time_s.map(|t| (m, t)))
                .collect();
            let times: Vec<f64> = means.iter().map(|&(_, t)| t).collect();
            let lo = means.iter().min_by(|a, b| a.1.total_cmp(&b.1));
            let hi = means.iter().max_by(|a, b| a.1.total_cmp(&b.1));
            Spread {
                algorithm: first[c].algorithm,
                robots: first[c].robots,
                maps: means.len(),
                min_s: lo.map(|x| x.1),
                median_s: crate::stats::median(&times),
                max_s: hi.map(|x| x.1),
                min_map: lo.map(|x| x.0),
                max_map: hi.map(|x| x.0),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::RunRecord;
    use gridswarm::policy::Policy;

    fn cell(t: Option<f64>) -> CellStats {
        let recs: Vec<RunRecord> = t
            .map(|t| RunRecord {
                seed: 0,
                search_time_s: t,
                rounds: 1,
                collisions: 0,
                targets_found: 9,
                complete: true,
                ..Default::default()
            })
            .into_iter()
            .collect();
        CellStats::of(Policy::Ru, 3, &recs)
    }

    #[test]
    fn spread_over_maps() {
        let per_map = vec![vec![cell(Some(30.0))], vec![cell(Some(10.0))], vec![cell(None)], vec![cell(Some(20.0))]];
        let s = &spreads(&per_map)[0];
        assert_eq!((s.maps, s.min_s, s.median_s, s.max_s), (3, Some(10.0), Some(20.0), Some(30.0)));
        assert_eq!((s.min_map, s.max_map), (Some(1), Some(0)));
    }

    #[test]
    fn maps_need_a_random_scenario() {
        let e = resolve("paper", Some(3)).unwrap_err();
        assert!(matches!(e, Error::Usage(_)) && e.to_string().contains("--maps needs a random scenario"), "{e}");
        let e = resolve(&format!("random:{}", u64::MAX), Some(2)).unwrap_err();
        assert!(e.to_string().contains("would pass 2^64 - 1"), "{e}");
        let maps = resolve("random:7,targets=3", Some(2)).unwrap();
        let names: Vec<&str> = maps.iter().map(|m| m.scenario.name.as_str()).collect();
        assert_eq!(names, ["random:7,targets=3", "random:8,targets=3"]);
        assert_eq!(resolve("paper", None).unwrap()[0].scenario.name, "paper");
    }
}
