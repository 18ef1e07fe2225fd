//! What the command's test files share: running the binary, a fresh
//! folder per test, and the assertion that a run succeeded. Each test file
//! uses part of it.
#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn gridswarm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gridswarm")).args(args).output().expect("the binary runs")
}

/// A fresh folder for one test, under cargo's per-target temporary folder,
/// grouped by test file.
pub fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(env!("CARGO_CRATE_NAME")).join(name);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

pub fn assert_ok(o: &Output) {
    assert!(o.status.success(), "exit {:?}\nstdout:\n{}\nstderr:\n{}", o.status, text(&o.stdout), text(&o.stderr));
}
