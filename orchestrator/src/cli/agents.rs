//! `--agent-bin PATH`: run `gridswarm run`'s robots with another agent
//! program, one built with `robot_agent::main_with` and a researcher's own
//! choice rules. The algorithms it lists (`PATH --list-rules`) become
//! names `--algorithm` accepts; this must happen before the arguments are
//! parsed, so `main` calls [`from_args`] first.

use std::ffi::OsString;
use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;

use gridswarm::choice::registry;

static AGENT_BIN: OnceLock<PathBuf> = OnceLock::new();

/// The agent program `--agent-bin` named, if any.
pub fn agent_bin() -> Option<PathBuf> {
    AGENT_BIN.get().cloned()
}

/// The value of `--agent-bin` among `args` (`--agent-bin P` or `--agent-bin=P`).
fn find(args: &[OsString]) -> Option<PathBuf> {
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let s = a.to_string_lossy();
        if s == "--agent-bin" {
            return it.next().map(PathBuf::from);
        }
        if let Some(v) = s.strip_prefix("--agent-bin=") {
            return Some(PathBuf::from(v));
        }
    }
    None
}

/// Reads `--agent-bin` from the command line and makes the agent's
/// algorithms known; without the flag, does nothing.
pub fn from_args(args: &[OsString]) -> Result<(), String> {
    let Some(bin) = find(args) else {
        return Ok(());
    };
    let out = Command::new(&bin)
        .arg("--list-rules")
        .output()
        .map_err(|e| format!("--agent-bin `{}`: cannot run it: {e}", bin.display()))?;
    if !out.status.success() {
        return Err(format!("--agent-bin `{}`: `--list-rules` failed ({})", bin.display(), out.status));
    }
    for name in String::from_utf8_lossy(&out.stdout).lines().map(str::trim).filter(|l| !l.is_empty()) {
        if name.parse::<gridswarm::policy::Policy>().is_err() {
            registry::announce(name).map_err(|e| format!("--agent-bin `{}`: {e}", bin.display()))?;
        }
    }
    let _ = AGENT_BIN.set(bin);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flag_is_found_in_both_spellings() {
        let a = |v: &[&str]| v.iter().map(OsString::from).collect::<Vec<_>>();
        assert_eq!(find(&a(&["run", "--agent-bin", "/x/a"])), Some(PathBuf::from("/x/a")));
        assert_eq!(find(&a(&["run", "--agent-bin=/x/b", "--seed", "1"])), Some(PathBuf::from("/x/b")));
        assert_eq!(find(&a(&["run", "--seed", "1"])), None);
    }

    #[test]
    fn an_agent_that_cannot_run_is_an_error() {
        let args = vec![OsString::from("--agent-bin"), OsString::from("/nonexistent/agent")];
        assert!(from_args(&args).unwrap_err().contains("cannot run it"));
    }
}
