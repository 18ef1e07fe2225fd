//! Provenance: what made an output, recorded beside it, and repeating it.
//! Every summary.json (under `provenance`), every results folder
//! (`provenance.json`, for the sweeps without a summary) and every report
//! says which build (version, git commit) ran which command line, on which
//! scenario (its full text and the SHA3-256 of it, as the run agreement
//! hashes it), with which parameters, seeds and starts, from when to when.
//! [`rerun`] repeats an output folder from that record alone.
//!
//! The clock times live only here, never in the files a rerun compares
//! (results.csv, runs.csv, trajectories, ...), which stay byte for byte the
//! same from one run of a command to the next. This module must never
//! change what a command computes: it only describes it.

pub mod recorded;
pub mod rerun;

use std::path::Path;
use std::sync::OnceLock;
use std::time::{SystemTime, UNIX_EPOCH};

use gridswarm::agreement::ScenarioId;
use gridswarm::grid::VertexId;
use gridswarm::scenario::{Scenario, StartRule};
use gridswarm::world::World;
use serde_json::{json, Value};

use crate::contract;
use crate::error::Result;
use crate::output;
use crate::report::{Block, Section};

/// The command's version (the workspace's).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
/// The git commit the command was built from, or "unknown" (build.rs).
pub const COMMIT: &str = env!("GRIDSWARM_COMMIT");
/// The file a results folder's provenance is written to.
pub const FILE: &str = "provenance.json";
/// The key of the provenance in a summary.json.
pub const KEY: &str = "provenance";

/// The command line and the time it started, set once by `main`.
struct Invocation {
    args: Vec<String>,
    started: SystemTime,
}

static INVOCATION: OnceLock<Invocation> = OnceLock::new();

/// Records the command line (`std::env::args_os`, each argument as UTF-8,
/// lossily) and the start time. A library caller that never calls it gets
/// `command: null` and its first record's time as the start.
pub fn begin(args: impl IntoIterator<Item = std::ffi::OsString>) {
    let args = args.into_iter().map(|a| a.to_string_lossy().into_owned()).collect();
    let _ = INVOCATION.set(Invocation { args, started: SystemTime::now() });
}

/// A time as `2026-12-03T18:27:00.123Z` (UTC, milliseconds).
pub fn timestamp(t: SystemTime) -> String {
    let d = t.duration_since(UNIX_EPOCH).unwrap_or_default();
    match time::OffsetDateTime::from_unix_timestamp(d.as_secs() as i64) {
        Ok(t) => format!(
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z",
            t.year(),
            t.month() as u8,
            t.day(),
            t.hour(),
            t.minute(),
            t.second(),
            d.subsec_millis()
        ),
        Err(_) => format!("{}s after 1970", d.as_secs()),
    }
}

/// What a command ran: filled in by the command, stamped by [`Record::value`].
pub struct Record<'a> {
    /// `--scenario` as given (a built-in name, a path, `random:...`), or
    /// `None` when the command chose its scenarios itself.
    pub scenario_arg: Option<&'a str>,
    /// Every parameter of the command, resolved (defaults included).
    pub parameters: Value,
    /// The base seed(s) and how each run's seed derives from them.
    pub seeds: Value,
    /// The start rule, and the vertices when one layout is used.
    pub starts: Value,
}

impl Record<'_> {
    /// The provenance object, its end time now. The scenario is loaded
    /// again from its argument, before the command's overrides (the
    /// command line holds those), so its text and hash are what a rerun
    /// loads and what the run agreement names.
    pub fn value(&self) -> Result<Value> {
        let scenario = match self.scenario_arg {
            Some(arg) => scenario_value(arg, &contract::load_scenario(arg)?),
            None => Value::Null,
        };
        let inv = INVOCATION.get();
        let now = SystemTime::now();
        Ok(json!({
            "tool": "gridswarm",
            "version": VERSION,
            "commit": COMMIT,
            "command": inv.map(|i| json!(i.args)).unwrap_or(Value::Null),
            "started_at": timestamp(inv.map_or(now, |i| i.started)),
            "ended_at": timestamp(now),
            "scenario": scenario,
            "parameters": self.parameters,
            "seeds": self.seeds,
            "starts": self.starts,
        }))
    }
}

/// The provenance of one run (`simulate`, `run`): its seed, and its start
/// rule and vertices (lattice coordinates, robot `k` at element `k`).
pub fn of_run(
    scenario_arg: &str,
    world: &World,
    starts: &[VertexId],
    rule: StartRule,
    seed: u64,
    parameters: Value,
) -> Result<Value> {
    let coords: Vec<[i32; 2]> = starts.iter().map(|&v| world.grid.coord(v)).map(|c| [c.i, c.j]).collect();
    Record {
        scenario_arg: Some(scenario_arg),
        parameters,
        seeds: json!({ "seed": seed }),
        starts: json!({ "rule": rule, "vertices": coords }),
    }
    .value()
}

/// A scenario as provenance names it: the argument, its name, its full
/// text as a scenario file and the SHA3-256 of that text.
fn scenario_value(arg: &str, s: &Scenario) -> Value {
    json!({
        "arg": arg,
        "name": s.name,
        "sha3_256": ScenarioId::of(s).sha3_256,
        "content": s.to_toml(""),
    })
}

/// Writes `provenance.json` into a results folder.
pub fn write(dir: &Path, provenance: &Value) -> Result<()> {
    output::write_json(&dir.join(FILE), provenance)
}

/// Stamps a results folder without a summary.json: writes its
/// `provenance.json` and adds the section to its report.
pub fn stamp(dir: &Path, page: &mut crate::report::Report, record: &Record) -> Result<()> {
    let v = record.value()?;
    write(dir, &v)?;
    page.sections.push(section(&v));
    Ok(())
}

/// The report's section: the build, the command line, the scenario's
/// hash and the times (the scenario's text and every parameter are in the
/// folder's provenance, not repeated on the page).
pub fn section(p: &Value) -> Section {
    let s = |v: &Value| v.as_str().map(str::to_string).unwrap_or_else(|| v.to_string());
    let command = p["command"].as_array().map(|a| a.iter().map(s).collect::<Vec<_>>().join(" "));
    let rows = [
        ("version", s(&p["version"])),
        ("commit", s(&p["commit"])),
        ("command", command.unwrap_or_else(|| "(a library call)".into())),
        ("scenario", s(&p["scenario"]["arg"])),
        ("scenario sha3-256", s(&p["scenario"]["sha3_256"])),
        ("seeds", s(&p["seeds"])),
        ("starts", s(&p["starts"]["rule"])),
        ("started", s(&p["started_at"])),
        ("ended", s(&p["ended_at"])),
    ];
    let rows = rows.into_iter().map(|(k, v)| (k.to_string(), v)).collect();
    Section::new(
        "Provenance",
        vec![
            Block::Params(rows),
            Block::Text(format!(
                "The scenario's full text and every parameter are in {FILE} or summary.json's `{KEY}`; \
                 `gridswarm rerun DIR` repeats this output from them and compares the bytes."
            )),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamps_are_utc_to_the_millisecond() {
        let t = UNIX_EPOCH + std::time::Duration::from_millis(1_796_322_420_123);
        assert_eq!(timestamp(t), "2026-12-03T18:27:00.123Z");
    }

    #[test]
    fn a_record_names_the_build_the_scenario_and_its_hash() {
        let r = Record {
            scenario_arg: Some("paper"),
            parameters: json!({"runs": 2}),
            seeds: json!(1),
            starts: json!({"rule": "fixed"}),
        };
        let v = r.value().unwrap();
        assert_eq!(v["version"], VERSION);
        assert!(COMMIT == "unknown" || COMMIT.len() == 40, "{COMMIT}");
        let sc = Scenario::parse(v["scenario"]["content"].as_str().unwrap(), "recorded").unwrap();
        assert_eq!(ScenarioId::of(&sc).sha3_256, v["scenario"]["sha3_256"], "the text hashes to the recorded hash");
        assert_eq!(sc, Scenario::builtin("paper").unwrap(), "the text is the whole scenario");
        assert!(v["started_at"].as_str().unwrap() <= v["ended_at"].as_str().unwrap());
    }
}
