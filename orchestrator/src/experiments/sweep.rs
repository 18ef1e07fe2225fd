//! Runs the jobs of a protocol experiment (`experiment failures`,
//! `experiment radio`) on the engine asked for: in-process on every core
//! (rayon over runs, results in job order whatever thread ran a job), or
//! one distributed run after another through [`crate::run::execute_as`].
//! Both give the same [`ProtoRun`]s for the same jobs.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use gridswarm::grid::VertexId;
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::{Scenario, StartRule};
use gridswarm::world::World;
use rayon::prelude::*;

use crate::contract::{self, Runner};
use crate::error::{Error, Result};
use crate::faults::{FaultPlan, RunBase};
use crate::progress::phase as progress_bar;
use crate::run;
use crate::tally::{ProtoRun, ProtoStats};

/// Which engine runs an experiment's runs.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Engine {
    /// Every robot a function call, every run on a rayon pool.
    #[default]
    InProcess,
    /// One world-server and one robot-agent process per robot (`gridswarm run`).
    Distributed,
}

impl Engine {
    /// The name `--engine` takes.
    pub fn name(self) -> &'static str {
        match self {
            Engine::InProcess => "in-process",
            Engine::Distributed => "distributed",
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            Engine::InProcess => "in-process: every robot a function call, runs in parallel on every core",
            Engine::Distributed => "distributed: one world-server and one robot-agent process per robot over iceoryx2",
        }
    }

    /// The `transport` of a summary, as `simulate` and `run` write it: how
    /// the robots of its runs were reached.
    pub fn transport(self) -> serde_json::Value {
        let name = match self {
            Engine::InProcess => "in-process",
            Engine::Distributed => "iceoryx2",
        };
        serde_json::json!({
            "name": name,
            "endpoints": [],
            "remote_agents": false,
            "security": crate::run::security(None),
        })
    }
}

/// What the protocol experiments take besides their own axes (the number
/// killed, the losses and retries).
#[derive(Clone, Debug)]
pub struct ProtocolOptions {
    pub scenario: String,
    pub algorithm: Policy,
    /// Runs per point; the experiment's default for the engine when `None`.
    pub runs: Option<u32>,
    pub seed: u64,
    pub situation: Option<Situation>,
    /// `--max-rounds`; `None`: the round budget ([`ProtocolOptions::with_round_limit`]).
    pub max_rounds: Option<u32>,
    pub engine: Engine,
    pub out: PathBuf,
    pub progress: bool,
}

impl ProtocolOptions {
    /// The shared options checked and the scenario loaded, with the
    /// situation asked for; `what` names the experiment in errors.
    pub fn load(&self, what: &str) -> Result<Scenario> {
        if self.runs == Some(0) {
            return Err(Error::Input("--runs must be at least 1".into()));
        }
        if !self.algorithm.on_grid() {
            return Err(Error::Usage(format!(
                "`experiment {what}` needs the radio protocol of the grid policies; `{}` moves off the grid",
                self.algorithm
            )));
        }
        let mut scenario = contract::load_scenario(&self.scenario)?;
        if let Some(s) = self.situation {
            scenario.situation = s;
        }
        contract::needs_targets(&scenario, &self.scenario)?;
        Ok(scenario)
    }

    /// The options with every run's round limit resolved: `--max-rounds`,
    /// or the round budget ([`crate::budget`]) of the largest of `teams`
    /// on the scenario's map, one number for the whole experiment, which
    /// its reproduce commands name.
    pub fn with_round_limit(&self, scenario: &Scenario, teams: &[usize]) -> Result<ProtocolOptions> {
        let mut limit = self.max_rounds;
        if limit.is_none() {
            let world = scenario.world();
            let mut most = 1;
            for &n in teams {
                let starts = contract::start_vertices(scenario, &world, n)?;
                most = most.max(crate::budget::rounds(&world, &starts).1);
            }
            limit = Some(most);
        }
        Ok(ProtocolOptions { max_rounds: limit, ..self.clone() })
    }

    /// Every run's round limit, once resolved; the old fixed limit before.
    pub fn rounds(&self) -> u32 {
        self.max_rounds.unwrap_or(gridswarm::scenario::limits::DEFAULT_MAX_ROUNDS)
    }

    /// Runs per point: `--runs`, or the experiment's default for the engine.
    pub fn runs_per(&self, in_process: u32, distributed: u32) -> u32 {
        self.runs.unwrap_or(match self.engine {
            Engine::InProcess => in_process,
            Engine::Distributed => distributed,
        })
    }

    /// Runs the planned jobs, each `(point, run, job)`; returns each run's
    /// figures with its point and run index, and the wall time in seconds.
    pub fn execute<K: Copy>(
        &self,
        scenario: &Scenario,
        planned: &[(K, u32, Job)],
    ) -> Result<(Vec<(K, u32, ProtoRun)>, f64)> {
        let jobs: Vec<Job> = planned.iter().map(|(_, _, j)| j.clone()).collect();
        let setting =
            Setting { scenario_arg: &self.scenario, scenario, algorithm: self.algorithm, max_rounds: self.rounds() };
        let started = Instant::now();
        let results = execute(self.engine, &setting, &jobs, self.progress)?;
        let wall_time_s = started.elapsed().as_secs_f64();
        Ok((planned.iter().zip(results).map(|((k, r, _), p)| (*k, *r, p)).collect(), wall_time_s))
    }
}

/// The statistics of the runs at `point`, of runs as
/// [`ProtocolOptions::execute`] returns them.
pub fn stats_at<K: PartialEq>(runs: &[(K, u32, ProtoRun)], point: &K) -> ProtoStats {
    let mine: Vec<ProtoRun> = runs.iter().filter(|r| r.0 == *point).map(|r| r.2.clone()).collect();
    ProtoStats::of(&mine)
}

/// What every run of an experiment shares.
struct Setting<'a> {
    /// The name or path the user gave (distributed runs load it again).
    pub scenario_arg: &'a str,
    /// Loaded, with the situation asked for.
    pub scenario: &'a Scenario,
    pub algorithm: Policy,
    pub max_rounds: u32,
}

/// One run: its robot count, seed, faults and radio.
#[derive(Clone, Debug)]
pub struct Job {
    pub robots: usize,
    pub seed: u64,
    pub plan: FaultPlan,
    /// Names the run in errors and warnings.
    pub what: String,
}

/// Runs every job; results in job order. Checks every job's plan first,
/// so a bad one fails before any run.
fn execute(engine: Engine, setting: &Setting, jobs: &[Job], progress: bool) -> Result<Vec<ProtoRun>> {
    for j in jobs {
        j.plan.check(setting.algorithm, j.robots)?;
    }
    match engine {
        Engine::InProcess => in_process(setting, jobs, progress),
        // The largest run refused before the first one starts.
        Engine::Distributed => crate::run::admit(jobs.iter().map(|j| j.robots).max().unwrap_or(1))
            .and_then(|()| distributed(setting, jobs, progress)),
    }
}

/// A world per retries value (it is a world parameter) and start vertices
/// per (world, robot count), built once before the runs.
struct Worlds {
    worlds: BTreeMap<Option<u32>, World>,
    starts: BTreeMap<(Option<u32>, usize), Vec<VertexId>>,
}

impl Worlds {
    fn build(scenario: &Scenario, jobs: &[Job]) -> Result<Self> {
        let mut w = Worlds { worlds: BTreeMap::new(), starts: BTreeMap::new() };
        for j in jobs {
            let key = j.plan.retries;
            let world = w.worlds.entry(key).or_insert_with(|| {
                let mut s = scenario.clone();
                j.plan.apply_params(&mut s.params);
                s.world()
            });
            if let std::collections::btree_map::Entry::Vacant(e) = w.starts.entry((key, j.robots)) {
                e.insert(contract::start_vertices(scenario, world, j.robots)?);
            }
        }
        Ok(w)
    }

    /// Each job's start vertices: the fixed layout, or its own draw when
    /// its plan asks for random starts (as `run` would draw them).
    fn starts_of<'a>(&'a self, scenario: &Scenario, jobs: &[Job]) -> Result<Vec<Cow<'a, [VertexId]>>> {
        jobs.iter()
            .map(|j| {
                let key = j.plan.retries;
                Ok(match j.plan.starts {
                    StartRule::Fixed => Cow::Borrowed(&self.starts[&(key, j.robots)][..]),
                    rule => Cow::Owned(contract::starts(scenario, &self.worlds[&key], j.robots, rule, j.seed)?),
                })
            })
            .collect()
    }
}

fn in_process(setting: &Setting, jobs: &[Job], progress: bool) -> Result<Vec<ProtoRun>> {
    let worlds = Worlds::build(setting.scenario, jobs)?;
    let starts = worlds.starts_of(setting.scenario, jobs)?;
    let lfp = contract::lfp_params(setting.scenario);
    let mut cfgs = Vec::with_capacity(jobs.len());
    for j in jobs {
        let mut cfg = RunConfig::new(setting.algorithm, j.seed, setting.scenario.situation);
        cfg.max_rounds = setting.max_rounds;
        // Numbers only: no poses, no raster pass.
        cfg.record_trajectories = false;
        cfg.measure_coverage = false;
        j.plan.configure(&mut cfg, j.robots)?;
        cfgs.push(cfg);
    }
    let bar = progress_bar(jobs.len() as u64, progress);
    let runs = jobs
        .par_iter()
        .zip(cfgs.par_iter().zip(&starts))
        .map(|(j, (cfg, s))| {
            let runner = Runner::new(&worlds.worlds[&j.plan.retries], lfp);
            let r = ProtoRun::of(&runner.run(s, cfg));
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    Ok(runs)
}

fn distributed(setting: &Setting, jobs: &[Job], progress: bool) -> Result<Vec<ProtoRun>> {
    let bar = progress_bar(jobs.len() as u64, progress);
    let mut warnings = Vec::new();
    let mut runs = Vec::with_capacity(jobs.len());
    for j in jobs {
        let base = RunBase {
            scenario: setting.scenario_arg.to_string(),
            algorithm: setting.algorithm,
            robots: Some(j.robots),
            seed: j.seed,
            situation: Some(setting.scenario.situation),
            max_rounds: setting.max_rounds,
            out: None,
            json: true,
        };
        let v = run::execute_as(&j.plan.run_options(base), &j.what, &mut warnings)
            .inspect_err(|_| bar.finish_and_clear())?;
        runs.push(ProtoRun::from_summary(j.seed, &v));
        bar.inc(1);
    }
    bar.finish_and_clear();
    for w in &warnings {
        eprintln!("{w}");
    }
    Ok(runs)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A job's plan decides its starts in-process as `run` does: a random
    /// one runs from its own seed's draw, not from the fixed layout.
    #[test]
    fn in_process_jobs_start_where_their_plan_says() {
        let scenario = Scenario::builtin("paper").unwrap();
        let setting =
            Setting { scenario_arg: "paper", scenario: &scenario, algorithm: Policy::Repulsive, max_rounds: 5000 };
        let job = |starts| Job {
            robots: 4,
            seed: 3,
            plan: FaultPlan { starts, ..FaultPlan::default() },
            what: String::new(),
        };
        let runs = in_process(&setting, &[job(StartRule::Fixed), job(StartRule::Random)], false).unwrap();
        let world = scenario.world();
        let drawn = contract::starts(&scenario, &world, 4, StartRule::Random, 3).unwrap();
        let mut cfg = RunConfig::new(Policy::Repulsive, 3, scenario.situation);
        cfg.max_rounds = 5000;
        cfg.record_trajectories = false;
        cfg.measure_coverage = false;
        let direct = ProtoRun::of(&Runner::new(&world, scenario.lfp).run(&drawn, &cfg));
        assert_eq!(runs[1], direct);
        assert_ne!(runs[0], runs[1], "the fixed layout is another run");
    }
}
