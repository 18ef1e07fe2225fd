//! The files of runs on disk: listing them, removing one run's, and
//! sweeping those of runs whose owner died. A run's files are the POSIX
//! shared memory under `/dev/shm` whose names start with its prefix, and
//! its iceoryx2 root folder ([`super::run_root`]).

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::{pid_alive, prefix_owner, run_root, PREFIX_HEAD};

/// Where the files of runs live: POSIX shared memory and iceoryx2's root.
fn file_roots(root: &Path) -> Vec<PathBuf> {
    vec![PathBuf::from("/dev/shm"), root.to_path_buf()]
}

/// Every file (not directory) under `dir`, recursively, whose name starts with `head`.
fn files_starting_with(dir: &Path, head: &str, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let path = e.path();
        let Ok(ft) = e.file_type() else { continue };
        if ft.is_dir() {
            files_starting_with(&path, head, out);
        } else if e.file_name().to_string_lossy().starts_with(head) {
            out.push(path);
        }
    }
}

/// Every file of the run with this prefix, under `/dev/shm` and `root`
/// (iceoryx2's root directory, see [`super::root_dir`]).
pub fn run_files(prefix: &str, root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for r in file_roots(root) {
        files_starting_with(&r, prefix, &mut out);
    }
    out.sort();
    // The run's root is itself under `/dev/shm`.
    out.dedup();
    out
}

/// Removes every file of the run with this prefix from `/dev/shm` and
/// `root`, and the node directories that held only its files. Returns how
/// many files it removed. Refuses a prefix [`new_prefix`] could not have
/// made, so a typo can never remove someone else's files. The run's own
/// root folder ([`run_root`]) goes as a whole: nothing else lives there.
pub fn cleanup_run(prefix: &str, root: &Path) -> io::Result<usize> {
    if prefix_owner(prefix).is_none() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("`{prefix}` is not a run prefix")));
    }
    let files = run_files(prefix, root);
    let mut removed = 0;
    let mut dirs = Vec::new();
    for f in &files {
        match fs::remove_file(f) {
            Ok(()) => removed += 1,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {}
            Err(e) => return Err(e),
        }
        if let Some(d) = f.parent() {
            dirs.push(d.to_path_buf());
        }
    }
    // A node's details live in a directory named by its id; once the
    // run's files are gone it is empty. `remove_dir` fails on a directory
    // that still holds anything, so nothing of another run is touched.
    dirs.sort();
    dirs.dedup();
    for d in dirs {
        if d.starts_with(root.join("nodes")) && d != root.join("nodes") {
            let _ = fs::remove_dir(&d);
        }
    }
    if root == run_root(prefix) {
        match fs::remove_dir_all(root) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
            _ => {}
        }
    }
    Ok(removed)
}

/// The prefixes of runs that have files under `/dev/shm` or `root`.
pub fn run_prefixes(root: &Path) -> Vec<String> {
    let mut files = Vec::new();
    for r in file_roots(root) {
        files_starting_with(&r, PREFIX_HEAD, &mut files);
    }
    let mut prefixes: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let name = f.file_name()?.to_string_lossy().into_owned();
            let end = name.find('_')?;
            let p = &name[..=end];
            prefix_owner(p).map(|_| p.to_string())
        })
        .collect();
    // A root folder whose files are already gone.
    prefixes.extend(root_folder_prefixes());
    prefixes.sort();
    prefixes.dedup();
    prefixes
}

/// The prefixes of the run root folders ([`run_root`]) in `/dev/shm`.
fn root_folder_prefixes() -> Vec<String> {
    let Ok(entries) = fs::read_dir("/dev/shm") else { return Vec::new() };
    entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let p = name.strip_prefix("gridswarm-")?.strip_suffix("iceoryx2")?;
            (prefix_owner(p).is_some() && run_root(p) == e.path()).then(|| p.to_string())
        })
        .collect()
}

/// Removes the files of every run whose owning process (the pid in its
/// prefix) is gone: what a SIGKILLed orchestrator left behind, its root
/// folder included. Returns the prefixes swept.
pub fn sweep_stale(root: &Path) -> Vec<String> {
    let mut swept = Vec::new();
    for p in run_prefixes(root) {
        let owner = prefix_owner(&p).expect("run_prefixes keeps run prefixes only");
        if owner != std::process::id() && !pid_alive(owner) && cleanup_run(&p, &run_root(&p)).is_ok() {
            swept.push(p);
        }
    }
    swept
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Held by the tests that sweep: a sweep removes every dead run's root
    /// folder in `/dev/shm`, so one test's sweep could remove the "dead"
    /// root another is still making (seen once: its `nodes` folder could
    /// not be made, its parent gone).
    static SWEEPING: std::sync::Mutex<()> = std::sync::Mutex::new(());

    #[test]
    fn cleanup_removes_only_its_run() {
        let _sweeping = SWEEPING.lock().unwrap_or_else(|e| e.into_inner());
        let dir = std::env::temp_dir().join(format!("gs-ipc-test-{}", std::process::id()));
        let nodes = dir.join("nodes").join("1234");
        fs::create_dir_all(&nodes).unwrap();
        let mine = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0xabc);
        let other = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0xdef);
        fs::write(dir.join(format!("{mine}a.service")), b"x").unwrap();
        fs::write(nodes.join(format!("{mine}b.details")), b"x").unwrap();
        fs::write(dir.join(format!("{other}c.service")), b"x").unwrap();
        assert_eq!(run_files(&mine, &dir).len(), 2);
        assert_eq!(cleanup_run(&mine, &dir).unwrap(), 2);
        assert!(run_files(&mine, &dir).is_empty());
        assert!(!nodes.exists(), "the emptied node directory goes too");
        assert_eq!(run_files(&other, &dir).len(), 1);
        assert!(run_prefixes(&dir).contains(&other));
        // Its owner (this process) is alive: not stale.
        assert!(!sweep_stale(&dir).contains(&other));
        assert!(cleanup_run("iox2_", &dir).is_err());
        fs::remove_dir_all(&dir).unwrap();
    }

    /// A dead run's root folder in `/dev/shm` goes with the sweep, even
    /// with none of its files left; a live run's stays.
    #[test]
    fn the_sweep_removes_a_dead_runs_empty_root_folder() {
        let _sweeping = SWEEPING.lock().unwrap_or_else(|e| e.into_inner());
        let dead = format!("{PREFIX_HEAD}{}x{:06x}_", u32::MAX - 7, 0x5ee);
        let live = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0x5ef);
        for p in [&dead, &live] {
            fs::create_dir_all(run_root(p).join("nodes")).unwrap();
        }
        let scratch = std::env::temp_dir().join(format!("gs-ipc-sweep-{}", std::process::id()));
        let swept = sweep_stale(&scratch);
        assert!(swept.contains(&dead), "{swept:?}");
        assert!(!run_root(&dead).exists());
        assert!(run_root(&live).exists(), "its owner is alive");
        fs::remove_dir_all(run_root(&live)).unwrap();
    }
}
