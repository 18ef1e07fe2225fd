//! The files of runs on disk: listing them, removing one run's, and
//! sweeping those of runs whose owner died. A run's files are the POSIX
//! shared memory directly in `/dev/shm` whose names start with its prefix,
//! and its iceoryx2 root folder there ([`super::run_root`]).
//!
//! `/dev/shm` is everyone's (SECURITY.md): another user can put anything
//! there under a run's names, a symlink to a folder of root's or a folder
//! of 20,000 files. So the clean-up lists `/dev/shm` once and never below
//! it, looks at each entry with `lstat` (a symlink is never followed), and
//! removes only regular files and real folders named by a run prefix and
//! owned by this process's uid. In the sticky `/dev/shm` nobody else can
//! rename or replace an entry of ours between that look and the removal.

use std::fs::{self, Metadata};
use std::io;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use super::{pid_alive, prefix_owner, PREFIX_HEAD};

/// Where POSIX shared memory lives, and with it every run's root folder.
const SHM: &str = "/dev/shm";

/// What a run keeps directly in `/dev/shm`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A shared-memory file, `<prefix>...`.
    File,
    /// The run's iceoryx2 root folder, `gridswarm-<prefix>iceoryx2`.
    Root,
}

/// An entry of `/dev/shm` named by a run prefix.
struct Entry {
    prefix: String,
    path: PathBuf,
    kind: Kind,
    meta: Metadata,
}

impl Entry {
    /// Made by gridswarm for a run of this uid: a regular file or a real
    /// folder as its name says (a symlink is neither), owned by this uid.
    fn ours(&self) -> bool {
        let shape = match self.kind {
            Kind::File => self.meta.file_type().is_file(),
            Kind::Root => self.meta.file_type().is_dir(),
        };
        shape && self.meta.uid() == my_uid()
    }
}

fn my_uid() -> u32 {
    // SAFETY: geteuid has no preconditions and cannot fail.
    unsafe { libc::geteuid() }
}

/// The run prefix an entry's name carries, and what kind of entry that name is.
fn classify(name: &str) -> Option<(&str, Kind)> {
    if let Some(p) = name.strip_prefix("gridswarm-").and_then(|r| r.strip_suffix("iceoryx2")) {
        return prefix_owner(p).map(|_| (p, Kind::Root));
    }
    let p = &name[..=name.find('_')?];
    prefix_owner(p).map(|_| (p, Kind::File))
}

/// The entries directly in `/dev/shm` named by a run prefix that `keep`
/// accepts, each looked at with `lstat`. One listing, never below it: what
/// others put in their own folders costs nothing, and an entry of theirs
/// costs one `lstat` only if its name has a run prefix's shape.
fn shm_entries(keep: impl Fn(&str) -> bool) -> Vec<Entry> {
    let Ok(dir) = fs::read_dir(SHM) else { return Vec::new() };
    dir.flatten()
        .filter_map(|e| {
            let name = e.file_name();
            let (prefix, kind) = classify(name.to_str()?)?;
            if !keep(prefix) {
                return None;
            }
            // DirEntry::metadata does not follow a symlink.
            let meta = e.metadata().ok()?;
            Some(Entry { prefix: prefix.to_string(), path: e.path(), kind, meta })
        })
        .collect()
}

/// Every regular file under `dir`, recursively, without following a symlink.
fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        match e.file_type() {
            Ok(t) if t.is_dir() => files_under(&e.path(), out),
            Ok(_) => out.push(e.path()),
            Err(_) => {}
        }
    }
}

/// Every file of the run with this prefix, whoever owns it: the entries
/// in `/dev/shm` named by it (a symlink among them is listed, not followed)
/// and the files in its root folder, if that is a real folder.
pub fn run_files(prefix: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in shm_entries(|p| p == prefix) {
        match e.kind {
            Kind::Root if e.meta.file_type().is_dir() => files_under(&e.path, &mut out),
            _ => out.push(e.path),
        }
    }
    out.sort();
    out
}

/// Removes one entry of ours; returns how many files went with it. The
/// root folder is this uid's and mode 0700 ([`super::private`]), so nobody
/// else put anything in it; `remove_dir_all` does not follow symlinks.
fn remove(e: &Entry) -> io::Result<usize> {
    let gone = match e.kind {
        Kind::File => fs::remove_file(&e.path).map(|()| 1),
        Kind::Root => {
            let mut files = Vec::new();
            files_under(&e.path, &mut files);
            fs::remove_dir_all(&e.path).map(|()| files.len())
        }
    };
    match gone {
        Err(err) if err.kind() == io::ErrorKind::NotFound => Ok(0),
        other => other,
    }
}

/// Removes every file of the run with this prefix that this uid made:
/// its shared-memory files in `/dev/shm` and its root folder as a whole.
/// Returns how many files it removed. Refuses a prefix [`new_prefix`]
/// could not have made, so a typo can never remove someone else's files;
/// leaves whatever another user put under the run's names.
///
/// [`new_prefix`]: super::new_prefix
pub fn cleanup_run(prefix: &str) -> io::Result<usize> {
    if prefix_owner(prefix).is_none() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("`{prefix}` is not a run prefix")));
    }
    let mut removed = 0;
    for e in shm_entries(|p| p == prefix).iter().filter(|e| e.ours()) {
        removed += remove(e)?;
    }
    Ok(removed)
}

/// Removes the files of every run of this uid whose owning process (the
/// pid in its prefix) is gone: what a SIGKILLed orchestrator left behind,
/// its root folder included. One listing of `/dev/shm` for all of them.
/// Returns the prefixes swept.
pub fn sweep_stale() -> Vec<String> {
    let me = std::process::id();
    let mut dead = std::collections::BTreeMap::<String, bool>::new();
    let mut swept = std::collections::BTreeSet::new();
    for e in shm_entries(|p| p.starts_with(PREFIX_HEAD)).iter().filter(|e| e.ours()) {
        let is_dead = *dead.entry(e.prefix.clone()).or_insert_with(|| {
            let owner = prefix_owner(&e.prefix).expect("classify keeps run prefixes only");
            owner != me && !pid_alive(owner)
        });
        if is_dead && remove(e).is_ok() {
            swept.insert(e.prefix.clone());
        }
    }
    swept.into_iter().collect()
}

/// Whether `path` is a folder this uid made, looked at without following
/// a symlink: what the orchestrator may remove of a dead run's temporary
/// folder in a directory others can write to.
pub fn is_own_folder(path: &Path) -> bool {
    fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_dir() && m.uid() == my_uid())
}

#[cfg(test)]
mod tests {
    use super::super::run_root;
    use super::*;

    /// Held by the tests that sweep: a sweep removes every dead run's root
    /// folder in `/dev/shm`, so one test's sweep could remove the "dead"
    /// root another is still making (seen once: its `nodes` folder could
    /// not be made, its parent gone).
    static SWEEPING: std::sync::Mutex<()> = std::sync::Mutex::new(());

    /// The root folder of the run with this prefix, made by hand.
    fn make_root(prefix: &str) -> PathBuf {
        let root = run_root(prefix);
        fs::create_dir_all(root.join("nodes").join("1234")).unwrap();
        root
    }

    #[test]
    fn cleanup_removes_only_its_run() {
        let _sweeping = SWEEPING.lock().unwrap_or_else(|e| e.into_inner());
        let mine = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0xabc);
        let other = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0xdef);
        let root = make_root(&mine);
        fs::write(root.join(format!("{mine}a.service")), b"x").unwrap();
        fs::write(root.join("nodes/1234").join(format!("{mine}b.details")), b"x").unwrap();
        let shm = Path::new(SHM).join(format!("{mine}c.data"));
        let theirs = Path::new(SHM).join(format!("{other}c.data"));
        fs::write(&shm, b"x").unwrap();
        fs::write(&theirs, b"x").unwrap();
        assert_eq!(run_files(&mine).len(), 3);
        assert_eq!(cleanup_run(&mine).unwrap(), 3);
        assert!(run_files(&mine).is_empty());
        assert!(!root.exists(), "the root folder goes as a whole");
        assert_eq!(run_files(&other), [theirs.clone()]);
        // Its owner (this process) is alive: not stale.
        assert!(!sweep_stale().contains(&other));
        assert!(cleanup_run("iox2_").is_err());
        assert_eq!(cleanup_run(&other).unwrap(), 1);
    }

    /// A dead run's root folder in `/dev/shm` goes with the sweep, even
    /// with none of its files left; a live run's stays.
    #[test]
    fn the_sweep_removes_a_dead_runs_empty_root_folder() {
        let _sweeping = SWEEPING.lock().unwrap_or_else(|e| e.into_inner());
        let dead = format!("{PREFIX_HEAD}{}x{:06x}_", u32::MAX - 7, 0x5ee);
        let live = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0x5ef);
        for p in [&dead, &live] {
            make_root(p);
        }
        let swept = sweep_stale();
        assert!(swept.contains(&dead), "{swept:?}");
        assert!(!run_root(&dead).exists());
        assert!(run_root(&live).exists(), "its owner is alive");
        fs::remove_dir_all(run_root(&live)).unwrap();
    }

    /// A symlink under a dead run's names, to a folder of ours and to a
    /// file of ours: neither the link nor what it points to is touched.
    #[test]
    fn the_sweep_never_follows_a_symlink() {
        let _sweeping = SWEEPING.lock().unwrap_or_else(|e| e.into_inner());
        let dead = format!("{PREFIX_HEAD}{}x{:06x}_", u32::MAX - 8, 0x5eb);
        let target = std::env::temp_dir().join(format!("gs-ipc-symlink-{}", std::process::id()));
        fs::create_dir_all(&target).unwrap();
        let precious = target.join(format!("{dead}precious"));
        fs::write(&precious, b"keep").unwrap();
        let links = [run_root(&dead), Path::new(SHM).join(format!("{dead}link"))];
        std::os::unix::fs::symlink(&target, &links[0]).unwrap();
        std::os::unix::fs::symlink(&precious, &links[1]).unwrap();
        let swept = sweep_stale();
        let left: Vec<bool> = links.iter().map(|l| fs::symlink_metadata(l).is_ok()).collect();
        for l in &links {
            let _ = fs::remove_file(l);
        }
        let kept = fs::read(&precious);
        fs::remove_dir_all(&target).unwrap();
        assert!(!swept.contains(&dead), "{swept:?}");
        assert_eq!(left, [true, true], "the links are not the run's: left alone");
        assert_eq!(kept.unwrap(), b"keep");
    }
}
