//! `gridswarm rerun DIR`: repeats the command that wrote an output folder,
//! from the folder's provenance alone (its recorded command line and the
//! scenario's recorded text, never the scenario file, which may have
//! changed since), into a new folder, and compares the outputs that must
//! repeat byte for byte. A `random:...` scenario is given again as its
//! text, which generates the same map everywhere (and `--maps K` needs it);
//! any other is written from its recorded text into a temporary file.
//!
//! It runs this same program as a child process, so the rerun goes through
//! exactly the parsing and defaults the original did; never a program the
//! folder names, and nothing that writes outside the new folder or listens
//! unless rerun's own command line asks ([`super::recorded`]).

use std::fs;
use std::io::Write;
use std::os::unix::fs::DirBuilderExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use gridswarm::agreement::ScenarioId;
use gridswarm::scenario::Scenario;
use serde_json::Value;

use super::recorded::{self, Allowed};
use super::{FILE, KEY};
use crate::error::{Error, Result};
use crate::rundir::read_text;

/// The outputs that repeat byte for byte; the others hold clock times
/// (provenance, reports, summaries with wall times) or pictures of them.
/// maps.csv is not among them (it holds each map's generation time), nor,
/// in a folder with one, claims.txt (which says how long they took).
pub const DETERMINISTIC: [&str; 13] = [
    "results.csv",
    "runs.csv",
    "claims.txt",
    "trajectories.jsonl",
    "rounds.csv",
    "world.json",
    "readings.csv",
    "cells.csv",
    "failures.csv",
    "failures-runs.csv",
    "radio.csv",
    "radio-runs.csv",
    "grids.csv",
];

/// What a rerun found.
pub struct Outcome {
    /// The new folder.
    pub out: PathBuf,
    /// Files compared, each with whether it is the same.
    pub compared: Vec<(String, Verdict)>,
    /// The recorded build, when it is not this one (then a difference may
    /// come from the code, not from the run).
    pub other_build: Option<String>,
    /// What of the recorded command was not repeated, and why.
    pub notes: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    Same,
    /// Differs from line `line` (1-based) on.
    Differs {
        line: usize,
    },
    /// The rerun did not write it.
    Missing,
}

impl Outcome {
    /// One line per file, then the verdict.
    pub fn text(&self) -> String {
        let mut s = match &self.other_build {
            Some(b) => format!("note: recorded by {b}, rerun by {} commit {}\n", super::VERSION, super::COMMIT),
            None => String::new(),
        };
        for n in &self.notes {
            s += &format!("note: {n}\n");
        }
        for (f, v) in &self.compared {
            s += &match v {
                Verdict::Same => format!("same     {f}\n"),
                Verdict::Differs { line } => format!("DIFFERS  {f} (from line {line} on)\n"),
                Verdict::Missing => format!("MISSING  {f} (the rerun did not write it)\n"),
            };
        }
        s
    }

    /// The files that are not the same.
    pub fn differing(&self) -> Vec<&str> {
        self.compared.iter().filter(|(_, v)| *v != Verdict::Same).map(|(f, _)| f.as_str()).collect()
    }
}

/// The provenance of an output folder: `provenance.json`, else the
/// `provenance` of its summary.json.
pub fn read(dir: &Path) -> Result<Value> {
    for (file, key) in [(FILE, None), ("summary.json", Some(KEY))] {
        let path = dir.join(file);
        if !path.is_file() {
            continue;
        }
        let v: Value = serde_json::from_str(&read_text(&path)?)
            .map_err(|e| Error::Read { path: path.clone(), message: e.to_string() })?;
        let v = match key {
            Some(k) => v[k].clone(),
            None => v,
        };
        if v.is_object() {
            return Ok(v);
        }
    }
    Err(Error::Input(format!(
        "`{}` holds no provenance ({FILE}, or summary.json with `{KEY}`): not an output folder of this gridswarm",
        dir.display()
    )))
}

/// Reruns the folder `dir` into `out` (default `dir/rerun`) and compares;
/// of the recorded command, only what `allowed` permits reaches outside
/// `out` ([`recorded::clean`]).
pub fn rerun(dir: &Path, out: Option<&Path>, allowed: &Allowed) -> Result<Outcome> {
    let p = read(dir)?;
    let cleaned = recorded::clean(&recorded_args(&p)?, allowed)?;
    let out = out.map(Path::to_path_buf).unwrap_or_else(|| dir.join("rerun"));
    let temp = std::env::temp_dir().join(format!("gridswarm-rerun-{}", std::process::id()));
    let result = (|| {
        let scenario = scenario_arg(&p, &temp)?;
        let mut args = cleaned.args;
        args.extend(["--out".to_string(), out.to_string_lossy().into_owned(), "--scenario".to_string(), scenario]);
        run_child(&args)
    })();
    let _ = fs::remove_dir_all(&temp);
    result?;
    let compared = DETERMINISTIC
        .iter()
        .filter(|f| dir.join(f).is_file())
        .filter(|&&f| f != "claims.txt" || !dir.join("maps.csv").exists())
        .map(|f| Ok((f.to_string(), compare(&dir.join(f), &out.join(f))?)))
        .collect::<Result<Vec<_>>>()?;
    if compared.is_empty() {
        return Err(Error::Input(format!("`{}` holds none of the outputs a rerun compares", dir.display())));
    }
    let recorded = (p["version"].as_str(), p["commit"].as_str());
    let other_build = (recorded != (Some(super::VERSION), Some(super::COMMIT)))
        .then(|| format!("{} commit {}", recorded.0.unwrap_or("?"), recorded.1.unwrap_or("?")));
    Ok(Outcome { out, compared, other_build, notes: cleaned.notes })
}

/// The recorded arguments after the program's name; refused when the
/// command cannot repeat its outputs.
fn recorded_args(p: &Value) -> Result<Vec<String>> {
    let cmd = p["command"].as_array().ok_or_else(|| {
        Error::Input("the provenance records no command line (the output was written by a library call)".into())
    })?;
    let args: Vec<String> = cmd.iter().skip(1).map(|a| a.as_str().unwrap_or_default().to_string()).collect();
    let sub: Vec<&str> = args.iter().take(2).map(String::as_str).collect();
    if sub.first() == Some(&"rerun") || sub == ["experiment", "scale"] {
        return Err(Error::Usage(format!(
            "`gridswarm {}` cannot be rerun: {}",
            sub.join(" "),
            if sub[0] == "rerun" { "it repeats another output" } else { "its outputs are wall-clock measurements" }
        )));
    }
    Ok(args)
}

/// The `--scenario` of the rerun: a random map's text, or the recorded
/// text written to a file in `temp`, a folder made for it (only this user
/// may enter it; one that exists already is refused, never reused), after
/// checking it hashes as recorded.
fn scenario_arg(p: &Value, temp: &Path) -> Result<String> {
    let s = &p["scenario"];
    let (arg, content, hash) = (s["arg"].as_str(), s["content"].as_str(), s["sha3_256"].as_str());
    let (Some(arg), Some(content), Some(hash)) = (arg, content, hash) else {
        return Err(Error::Input("the provenance records no scenario text and hash".into()));
    };
    let parsed = Scenario::parse(content, "the recorded scenario").map_err(|e| Error::Scenario(e.to_string()))?;
    if ScenarioId::of(&parsed).sha3_256 != hash {
        return Err(Error::Input(format!("the recorded scenario text does not hash to the recorded sha3 {hash}")));
    }
    if arg.starts_with("random:") {
        return Ok(arg.to_string());
    }
    fs::DirBuilder::new().mode(0o700).create(temp).map_err(Error::write(temp))?;
    let file = temp.join("scenario.toml");
    let mut f = fs::OpenOptions::new().write(true).create_new(true).open(&file).map_err(Error::write(&file))?;
    f.write_all(content.as_bytes()).map_err(Error::write(&file))?;
    Ok(file.to_string_lossy().into_owned())
}

/// Runs this program with `args`; its stdout discarded, its stderr shown.
/// A search that ended incomplete (status 3), with robots collided (4) or
/// past a stated bound (5) repeated its outputs too.
fn run_child(args: &[String]) -> Result<()> {
    use crate::error::{EXIT_COLLISION, EXIT_INCOMPLETE, EXIT_PAST_BOUND};
    let exe = std::env::current_exe().map_err(|e| Error::Run(format!("cannot find this program: {e}")))?;
    let status = Command::new(exe)
        .args(args)
        .stdout(Stdio::null())
        .status()
        .map_err(|e| Error::Run(format!("cannot start the rerun: {e}")))?;
    match status.code() {
        Some(0) => Ok(()),
        Some(c) if [EXIT_INCOMPLETE, EXIT_COLLISION, EXIT_PAST_BOUND].iter().any(|&e| c == i32::from(e)) => Ok(()),
        _ => Err(Error::Run(format!("the rerun `gridswarm {}` failed ({status})", args.join(" ")))),
    }
}

/// Whether `new` has the bytes of `old`, and if not the first line that differs.
fn compare(old: &Path, new: &Path) -> Result<Verdict> {
    let a = fs::read(old).map_err(|e| Error::Read { path: old.to_path_buf(), message: e.to_string() })?;
    let Ok(b) = fs::read(new) else {
        return Ok(Verdict::Missing);
    };
    if a == b {
        return Ok(Verdict::Same);
    }
    let at = a.iter().zip(&b).position(|(x, y)| x != y).unwrap_or(a.len().min(b.len()));
    Ok(Verdict::Differs { line: 1 + a[..at].iter().filter(|&&c| c == b'\n').count() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_and_rerun_itself_are_refused() {
        let p = serde_json::json!({"command": ["gridswarm", "experiment", "scale", "--runs", "1"]});
        assert!(matches!(recorded_args(&p), Err(Error::Usage(m)) if m.contains("wall-clock")));
        let p = serde_json::json!({"command": null});
        assert!(recorded_args(&p).is_err());
    }
}
