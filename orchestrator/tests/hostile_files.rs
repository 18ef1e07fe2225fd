//! The hostile scenario files of issue 11 (shared/tests/fixtures/hostile)
//! through the real binary: `check` and `simulate` on each end within the
//! issue's 5 s with one `error:` line naming the field, never a panic, a
//! hang or an abort.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The bound for any file of at most 1 MB.
const BOUND: Duration = Duration::from_secs(5);

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/tests/fixtures/hostile");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
}

/// Runs the binary, killing it (and failing) past [`BOUND`].
fn within_bound(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gridswarm"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > BOUND {
            let _ = child.kill();
            let _ = child.wait();
            panic!("gridswarm {args:?} still running after {BOUND:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

#[test]
fn check_and_simulate_refuse_every_hostile_file_quickly() {
    let files = fixtures();
    assert!(files.len() >= 6, "{files:?}");
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let field = text
            .lines()
            .find_map(|l| l.strip_prefix("# expect:"))
            .and_then(|l| l.split('|').next())
            .map(str::trim)
            .expect("an expect line");
        let path = file.to_str().unwrap();
        for args in [vec!["check", path], vec!["simulate", "--scenario", path]] {
            let out = within_bound(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
            assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
            assert!(err.starts_with("error: ") && err.contains(&format!(": {field}: ")), "{args:?}: {err}");
        }
    }
}
