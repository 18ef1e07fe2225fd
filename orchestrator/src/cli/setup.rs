//! `gridswarm setup`: one robot's setup file (`SetupFile`: its
//! `RobotSetup` and the run's agreement), exactly as `gridswarm run` writes
//! it for the agents it starts, for a robot-agent started by hand on
//! another host (`robot-agent --setup FILE`). The agent never reads a
//! scenario: the orchestrator derives its setup from the scenario, seed and
//! robot number, the way firmware is flashed before a run, and the world
//! still checks the agreement it presents.

use std::fs;
use std::path::{Path, PathBuf};

use gridswarm::outcome::RunConfig;
use gridswarm::params::{Order, Situation, SlotRule};
use gridswarm::policy::Policy;
use gridswarm::setup::SetupFile;

use crate::error::{Error, Result};
use crate::run::Overrides;

#[derive(clap::Args, Debug, Clone)]
pub struct SetupArgs {
    /// The run's key, as the world's `--remote-agents KEY` (the agent's `--prefix`).
    #[arg(long)]
    pub key: String,
    /// This robot's number, 0 to the team's size - 1.
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..gridswarm::ipc::MAX_ROBOTS as i64))]
    pub robot: u32,
    /// The team's size, as the world's `--robots` [default: the scenario's].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=gridswarm::ipc::MAX_ROBOTS as i64))]
    pub robots: Option<u32>,
    /// Built-in scenario, a TOML file, a ROS map_server map (NAME.yaml) or random:SEED[,options],
    /// as the world's `--scenario`.
    #[arg(long, default_value = "paper")]
    pub scenario: String,
    /// repulsive, sequential, ru, escape, frontier, frontier-coord, frontier-sensed,
    /// frontier-sensed-coord, or one --agent-bin lists, as the world's.
    #[arg(long, default_value = "repulsive")]
    pub algorithm: Policy,
    /// The run's seed, as the world's.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// 1: the number of targets is known; 2: it is not [default: the scenario's].
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub situation: Option<u8>,
    /// Extra copies of every frame, as the world's [default: the scenario's params.retries].
    #[arg(long, value_name = "R", value_parser = clap::value_parser!(u32).range(0..=254))]
    pub retries: Option<u32>,
    /// The slot rule, as the world's (adaptive or fixed) [default: the scenario's params.slot].
    #[arg(long, value_name = "RULE")]
    pub slot: Option<SlotRule>,
    /// The choice order, as the world's (paper or local) [default: the scenario's params.order].
    #[arg(long, value_name = "ORDER")]
    pub order: Option<Order>,
    /// The agent program whose own choice rules `--algorithm` may name.
    #[arg(long)]
    pub agent_bin: Option<PathBuf>,
    /// The file to write (replaced if it exists).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
}

impl SetupArgs {
    fn overrides(&self) -> Overrides {
        Overrides {
            situation: self.situation.and_then(Situation::from_number),
            retries: self.retries,
            slot: self.slot,
            order: self.order,
        }
    }
}

/// Robot `a.robot`'s setup file for run `a.key`: the one `gridswarm run`
/// would write for it (the same overrides, world and agreement).
pub fn setup_file(a: &SetupArgs) -> Result<SetupFile> {
    if !a.algorithm.on_grid() {
        return Err(Error::Usage(format!(
            "`{}` is not a robot program: a robot-agent runs grid policies only",
            a.algorithm
        )));
    }
    gridswarm::transport::check_key(&a.key).map_err(|e| Error::Usage(format!("--key: {e}")))?;
    let (scenario, id) = a.overrides().load(&a.scenario)?;
    let world = scenario.world();
    let cfg = RunConfig::new(a.algorithm, a.seed, scenario.situation);
    // A number outside the team is the world's to refuse, in its words.
    let team = a.robots.map_or(scenario.robots, |n| n as usize);
    Ok(SetupFile { key: a.key.clone(), scenario: id, setup: cfg.robot_setup(&world, a.robot as usize, team) })
}

/// Writes the file (whole or not at all); returns what to tell the user.
pub fn write(a: &SetupArgs) -> Result<String> {
    let file = setup_file(a)?;
    let text = serde_json::to_string(&file).map_err(|e| Error::Run(format!("cannot encode the setup: {e}")))?;
    replace(&a.out, &text)?;
    let sc = &file.scenario;
    Ok(format!(
        "robot {} of run `{}` ({} sha3 {}, seed {}, {}) in {}; on its host:\n  \
         robot-agent --transport zenoh --prefix {} --setup {} --connect ... (--credentials DIR or --insecure)\n",
        a.robot,
        a.key,
        sc.name,
        &sc.sha3_256[..12],
        a.seed,
        a.algorithm,
        a.out.display(),
        a.key,
        a.out.display(),
    ))
}

/// Writes `text` beside `path` and renames it into place.
fn replace(path: &Path, text: &str) -> Result<()> {
    let name = path.file_name().ok_or_else(|| Error::Usage(format!("--out `{}` is not a file", path.display())))?;
    let tmp = path.with_file_name(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    fs::write(&tmp, text).map_err(Error::write(&tmp))?;
    fs::rename(&tmp, path).map_err(|e| {
        let _ = fs::remove_file(&tmp);
        Error::write(path)(e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::{self, RunOptions};

    fn args(scenario: &str, algorithm: Policy, robot: u32) -> SetupArgs {
        SetupArgs {
            key: "key".into(),
            robot,
            robots: Some(13),
            scenario: scenario.into(),
            algorithm,
            seed: 41,
            situation: None,
            retries: None,
            slot: None,
            order: None,
            agent_bin: None,
            out: PathBuf::from("unused.json"),
        }
    }

    /// An agent started by hand holds exactly what `run` hands the agents it starts.
    #[test]
    fn a_setup_is_the_one_run_writes() {
        let cases = [
            ("paper", Policy::Repulsive, Situation::Two, None, None, None, 7),
            ("paper", Policy::Sequential, Situation::One, Some(2), None, Some(Order::Local), 12),
            ("random:3", Policy::Escape, Situation::One, None, Some(SlotRule::Fixed), None, 0),
        ];
        for (scenario, policy, situation, retries, slot, order, robot) in cases {
            let mut o = RunOptions::for_experiment(scenario.into(), policy, 13, 41, situation, 0, 100);
            (o.retries, o.slot, o.order) = (retries, slot, order);
            let plan = run::plan(&o).unwrap();
            let mut a = args(scenario, policy, robot);
            a.situation = Some(if situation == Situation::One { 1 } else { 2 });
            (a.retries, a.slot, a.order) = (retries, slot, order);
            let file = setup_file(&a).unwrap();
            assert_eq!(
                file.setup,
                plan.cfg.robot_setup(&plan.world, robot as usize, 13),
                "{scenario} {policy} {robot}"
            );
            assert_eq!(file.agreement(), plan.agreement("key"), "{scenario} {policy} {robot}");
        }
    }

    #[test]
    fn what_no_agent_can_run_is_refused_as_usage() {
        let err = setup_file(&args("paper", Policy::Lfp, 0)).unwrap_err();
        assert!(matches!(err, Error::Usage(_)) && err.to_string().contains("lfp"), "{err}");
        let mut a = args("paper", Policy::Repulsive, 0);
        a.key = "a/b".into();
        assert!(setup_file(&a).is_err_and(|e| matches!(e, Error::Usage(_)) && e.to_string().contains("--key")));
        assert!(setup_file(&args("nowhere", Policy::Repulsive, 0)).is_err());
    }

    #[test]
    fn the_file_is_written_whole_and_reads_back() {
        let dir = std::env::temp_dir().join(format!("gridswarm-setup-test-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let mut a = args("small", Policy::Frontier, 1);
        a.out = dir.join("robot-1.json");
        let said = write(&a).unwrap();
        assert!(said.contains("--setup ") && said.contains("robot-1.json"), "{said}");
        let back: SetupFile = serde_json::from_str(&fs::read_to_string(&a.out).unwrap()).unwrap();
        assert_eq!(back, setup_file(&a).unwrap());
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left");
        a.out = dir.join("missing/robot-1.json");
        assert!(write(&a).is_err_and(|e| e.to_string().contains("missing")));
        fs::remove_dir_all(&dir).unwrap();
    }
}
