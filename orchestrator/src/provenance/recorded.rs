//! What of a recorded command line a rerun repeats (issue 36, point 9). A
//! results folder is data, perhaps someone else's: nothing it names is
//! executed, written to or served unless the rerun's own command line
//! asks for it.
//!
//! - Only commands that write a results folder are repeated (`simulate`,
//!   `run`, `experiment` and its `failures`, `radio` and `readings`).
//! - `--agent-bin PATH` (a program `run` executes) is repeated only if
//!   rerun's own command line gives the same PATH; otherwise the rerun is
//!   refused, naming the option.
//! - `--mcap FILE` is dropped: the MCAP file is a view of the run, which a
//!   rerun does not compare, and the path is the recorded command's, which
//!   may lie anywhere; writing it into the output folder instead would
//!   repeat nothing a rerun checks.
//! - `--live [ADDR]` and `--speed` are dropped unless rerun's own command
//!   line has `--live [ADDR]`, which then serves at rerun's address.
//! - zenoh's flags (`--transport zenoh`, `--listen`, `--remote-agents`,
//!   `--credentials`, `--insecure`, `--insecure-network`) are dropped: a
//!   zenoh world listens on a network socket, so the rerun runs over
//!   iceoryx2 (shared memory), whose outputs are the same byte for byte.
//! - `--out` and `--scenario` are the rerun's own (its folder, and the
//!   recorded scenario text).
//!
//! Every drop is said in a note. Any other flag is passed on as recorded:
//! it changes what the run computes, which the rerun must repeat.

use std::net::SocketAddr;
use std::path::PathBuf;

use gridswarm::agreement::shown;

use crate::error::{Error, Result};

/// What rerun's own command line allows of the recorded one.
#[derive(Clone, Debug, Default)]
pub struct Allowed {
    /// `rerun --agent-bin PATH`: the agent program the user trusts.
    pub agent_bin: Option<PathBuf>,
    /// `rerun --live [ADDR]`: serve the rerun live, here.
    pub live: Option<SocketAddr>,
}

/// The command line to run, and what was dropped from the recorded one.
#[derive(Debug, PartialEq)]
pub struct Cleaned {
    pub args: Vec<String>,
    pub notes: Vec<String>,
}

/// How a recorded flag is treated.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// The rerun's own value replaces it.
    Own,
    AgentBin,
    Mcap,
    Live,
    Speed,
    /// zenoh's: the world would listen on a network socket.
    Network,
}

/// The flags a rerun does not pass on as recorded, and whether each takes a
/// value (`Some(true)`), none (`Some(false)`) or an optional one (`None`).
const GUARDED: [(&str, Kind, Option<bool>); 12] = [
    ("--out", Kind::Own, Some(true)),
    ("--scenario", Kind::Own, Some(true)),
    ("--agent-bin", Kind::AgentBin, Some(true)),
    ("--mcap", Kind::Mcap, Some(true)),
    ("--live", Kind::Live, None),
    ("--speed", Kind::Speed, Some(true)),
    ("--transport", Kind::Network, Some(true)),
    ("--listen", Kind::Network, Some(true)),
    ("--remote-agents", Kind::Network, Some(true)),
    ("--credentials", Kind::Network, Some(true)),
    ("--insecure", Kind::Network, Some(false)),
    ("--insecure-network", Kind::Network, Some(false)),
];

/// The commands whose outputs a rerun repeats; `experiment scale` is
/// refused before ([`super::rerun`]).
pub const COMMANDS: [&str; 3] = ["simulate", "run", "experiment"];
pub const EXPERIMENTS: [&str; 3] = ["failures", "radio", "readings"];

/// Whether a rerun guards the flag `--name` (its tests check that every
/// option taking a path or an address is guarded).
pub fn guards(name: &str) -> bool {
    GUARDED.iter().any(|g| g.0 == name)
}

/// One recorded flag the rerun guards, with its value if it has one.
struct Found {
    kind: Kind,
    flag: &'static str,
    value: Option<String>,
}

/// The recorded arguments (after the program's name) with every guarded
/// flag taken out, checked against `allowed`, and the rerun's own `--live`
/// added; `--out` and `--scenario` are left for the caller to add.
pub fn clean(args: &[String], allowed: &Allowed) -> Result<Cleaned> {
    let command = command_of(args)?;
    let (mut kept, found) = split(args);
    let mut notes = Vec::new();
    agent_bin(&found, allowed, &mut kept)?;
    for f in &found {
        let value = f.value.as_deref().unwrap_or_default();
        match f.kind {
            Kind::Mcap => notes.push(format!(
                "the recorded `--mcap {value}` is not written: a rerun writes only into its output folder \
                 (and does not compare the MCAP view)"
            )),
            Kind::Live if allowed.live.is_none() => notes.push(format!(
                "the recorded `--live{}` is not served: a rerun opens no socket unless its own command line \
                 says `--live`",
                f.value.as_ref().map(|v| format!(" {v}")).unwrap_or_default()
            )),
            Kind::Speed if allowed.live.is_some() => kept.extend([f.flag.to_string(), value.to_string()]),
            _ => {}
        }
    }
    if found.iter().any(|f| f.kind == Kind::Network) {
        notes.push(
            "the recorded zenoh flags (a world listening on a network socket) are dropped: the rerun goes \
             over iceoryx2, shared memory, whose outputs are the same byte for byte"
                .into(),
        );
    }
    if let Some(addr) = allowed.live {
        if !matches!(command, "simulate" | "run") {
            return Err(Error::Usage(format!("--live: `gridswarm {command}` has no live view to serve")));
        }
        kept.extend(["--live".to_string(), addr.to_string()]);
    }
    Ok(Cleaned { args: kept, notes })
}

/// The recorded subcommand, if it is one whose outputs a rerun repeats.
fn command_of(args: &[String]) -> Result<&str> {
    let first = args.first().map(String::as_str).unwrap_or_default();
    let second = args.get(1).map(String::as_str).filter(|a| !a.starts_with('-'));
    let known = COMMANDS.contains(&first) && (first != "experiment" || second.is_none_or(|k| EXPERIMENTS.contains(&k)));
    if !known {
        let head: Vec<&str> = args.iter().take(2).map(String::as_str).collect();
        return Err(Error::Input(format!(
            "the recorded command `gridswarm {}` is not one whose outputs a rerun repeats \
             (simulate, run, experiment, experiment failures, radio or readings)",
            shown(&head.join(" "))
        )));
    }
    Ok(first)
}

/// The arguments without the guarded flags, and those flags.
fn split(args: &[String]) -> (Vec<String>, Vec<Found>) {
    let (mut kept, mut found) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < args.len() {
        let a = &args[i];
        i += 1;
        let (name, inline) = match a.split_once('=') {
            Some((n, v)) if n.starts_with("--") => (n, Some(v.to_string())),
            _ => (a.as_str(), None),
        };
        let Some(&(flag, kind, takes)) = GUARDED.iter().find(|g| g.0 == name) else {
            kept.push(a.clone());
            continue;
        };
        let value = match (inline, takes) {
            (Some(v), _) => Some(v),
            (None, Some(false)) => None,
            // An optional value is the next argument unless that is a flag.
            (None, None) if args.get(i).is_none_or(|n| n.starts_with('-')) => None,
            (None, _) => {
                i += 1;
                args.get(i - 1).cloned()
            }
        };
        found.push(Found { kind, flag, value });
    }
    (kept, found)
}

/// Keeps the recorded `--agent-bin` if rerun's own command line names the
/// same program; refuses the rerun otherwise.
fn agent_bin(found: &[Found], allowed: &Allowed, kept: &mut Vec<String>) -> Result<()> {
    let recorded: Vec<&str> =
        found.iter().filter(|f| f.kind == Kind::AgentBin).map(|f| f.value.as_deref().unwrap_or_default()).collect();
    let own = allowed.agent_bin.as_ref().map(|p| p.to_string_lossy().into_owned());
    match (recorded.as_slice(), own) {
        ([], None) => Ok(()),
        ([r], Some(o)) if *r == o => {
            kept.extend(["--agent-bin".to_string(), o]);
            Ok(())
        }
        ([], Some(o)) => {
            Err(Error::Usage(format!("--agent-bin `{}`: the recorded command runs no agent program", shown(&o))))
        }
        (r, o) => {
            let r = shown(&r.join(" ")).into_owned();
            let own = o.map(|o| format!(" (rerun's own --agent-bin is `{}`)", shown(&o))).unwrap_or_default();
            Err(Error::Usage(format!(
                "the recorded command runs the agent program `--agent-bin {r}`, and a rerun executes no program \
                 its folder names{own}: to run it, give rerun the same `--agent-bin {r}`"
            )))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn what_changes_the_run_is_kept_and_what_reaches_outside_is_dropped() {
        let args = v(&[
            "run",
            "--seed",
            "4",
            "--mcap",
            "/tmp/x.mcap",
            "--live",
            "0.0.0.0:9",
            "--speed",
            "5x",
            "--transport",
            "zenoh",
            "--listen=tcp/0.0.0.0:7447",
            "--insecure",
            "--insecure-network",
            "--robots",
            "3",
            "--out",
            "o",
            "--scenario=s",
        ]);
        let c = clean(&args, &Allowed::default()).unwrap();
        assert_eq!(c.args, v(&["run", "--seed", "4", "--robots", "3"]));
        let notes = c.notes.join("\n");
        for want in ["`--mcap /tmp/x.mcap` is not written", "`--live 0.0.0.0:9` is not served", "over iceoryx2"] {
            assert!(notes.contains(want), "{want} in {notes}");
        }
        // `--live` with no value, before another flag.
        let c = clean(&v(&["simulate", "--live", "--seed", "2"]), &Allowed::default()).unwrap();
        assert_eq!(c.args, v(&["simulate", "--seed", "2"]));
        assert!(c.notes[0].contains("`--live` is not served"), "{:?}", c.notes);
    }

    #[test]
    fn live_is_served_only_where_rerun_says() {
        let live = Some("127.0.0.1:8770".parse().unwrap());
        let allowed = Allowed { live, ..Allowed::default() };
        let c = clean(&v(&["simulate", "--live=0.0.0.0:1", "--speed", "4x"]), &allowed).unwrap();
        assert_eq!(c.args, v(&["simulate", "--speed", "4x", "--live", "127.0.0.1:8770"]));
        let e = clean(&v(&["experiment", "--runs", "2"]), &allowed).unwrap_err();
        assert!(matches!(&e, Error::Usage(m) if m.contains("--live")), "{e}");
    }

    #[test]
    fn an_agent_program_runs_only_if_rerun_names_the_same() {
        let args = v(&["run", "--agent-bin", "/tmp/evil", "--seed", "2"]);
        let e = clean(&args, &Allowed::default()).unwrap_err();
        assert!(matches!(&e, Error::Usage(m) if m.contains("--agent-bin /tmp/evil")), "{e}");
        let other = Allowed { agent_bin: Some("/tmp/mine".into()), ..Allowed::default() };
        let e = clean(&args, &other).unwrap_err();
        assert!(e.to_string().contains("rerun's own --agent-bin is `/tmp/mine`"), "{e}");
        let same = Allowed { agent_bin: Some("/tmp/evil".into()), ..Allowed::default() };
        assert_eq!(clean(&args, &same).unwrap().args, v(&["run", "--seed", "2", "--agent-bin", "/tmp/evil"]));
        let e = clean(&v(&["run", "--agent-bin=/tmp/evil"]), &Allowed::default()).unwrap_err();
        assert!(e.to_string().contains("`--agent-bin /tmp/evil`"), "{e}");
        assert!(clean(&v(&["run"]), &same).is_err_and(|e| e.to_string().contains("runs no agent program")));
    }

    #[test]
    fn only_commands_that_write_a_results_folder_are_repeated() {
        for ok in [&["simulate"][..], &["experiment", "--runs", "2"], &["experiment", "readings"]] {
            assert!(clean(&v(ok), &Allowed::default()).is_ok(), "{ok:?}");
        }
        for bad in [&["export-map", "paper"][..], &["setup", "--key", "k"], &["credentials"], &["experiment", "x"], &[]]
        {
            let e = clean(&v(bad), &Allowed::default()).unwrap_err();
            assert!(e.to_string().contains("is not one whose outputs a rerun repeats"), "{bad:?}: {e}");
        }
    }
}
