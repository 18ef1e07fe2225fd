//! Stamps the command with the git commit it was built from
//! (`GRIDSWARM_COMMIT`, recorded in every output's provenance): `git
//! rev-parse HEAD` when the sources are a git checkout and git is there,
//! else "unknown", never a failed build. Rebuilt when HEAD moves (a
//! checkout, a commit) and only then.

use std::path::{Path, PathBuf};
use std::process::Command;

/// `git ARGS` in the crate's folder, its trimmed output when it succeeds.
fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).current_dir(dir).output().ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    (out.status.success() && !text.trim().is_empty()).then(|| text.trim().to_string())
}

/// A path `git rev-parse --git-path` gives, relative to `dir` unless absolute.
fn git_path(dir: &Path, name: &str) -> Option<PathBuf> {
    git(dir, &["rev-parse", "--git-path", name]).map(|p| dir.join(p))
}

fn main() {
    let dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    println!("cargo:rerun-if-changed=build.rs");
    let commit =
        git(&dir, &["rev-parse", "HEAD"]).filter(|c| c.len() == 40 && c.bytes().all(|b| b.is_ascii_hexdigit()));
    if commit.is_some() {
        // HEAD names the branch; the branch's ref (or packed-refs) names the commit.
        let mut watched: Vec<PathBuf> = git_path(&dir, "HEAD").into_iter().collect();
        if let Some(r) = git(&dir, &["symbolic-ref", "-q", "HEAD"]) {
            watched.extend(git_path(&dir, &r));
        }
        watched.extend(git_path(&dir, "packed-refs"));
        // A path that does not exist would make cargo rerun this every build.
        for p in watched.iter().filter(|p| p.exists()) {
            println!("cargo:rerun-if-changed={}", p.display());
        }
    }
    println!("cargo:rustc-env=GRIDSWARM_COMMIT={}", commit.as_deref().unwrap_or("unknown"));
}
