//! Output folders that are replaced whole or not at all.
//!
//! A command writes its files into a fresh hidden folder beside the one
//! asked for, then renames it into place: a reader never sees the files of
//! two runs mixed in one folder, and a run that fails part-way (a full disk,
//! an error, Ctrl-C) leaves the previous results intact. Creating the
//! staging folder first is also the check that the place is writable, done
//! before any run starts.
//!
//! A folder is replaced only if it is empty or was written by gridswarm
//! (it holds [`MARKER`]): `--out ~` must never delete a home directory.

use std::fs;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// The file that marks a folder as gridswarm's output, safe to replace.
pub const MARKER: &str = ".gridswarm-output";

/// Files gridswarm writes: a folder holding nothing else (written before
/// [`MARKER`] existed) is gridswarm's output too.
const OUR_FILES: [&str; 24] = [
    "claims.txt",
    "failures-runs.csv",
    "failures.csv",
    "failures.svg",
    "fig7.svg",
    "grids.csv",
    "grids.html",
    "maps.csv",
    "radio-runs.csv",
    "radio.csv",
    "radio.svg",
    "replay.html",
    "report.html",
    "results.csv",
    "rounds.csv",
    "routes.svg",
    "runs.csv",
    "scale-runs.csv",
    "scale.csv",
    "scale.svg",
    "summary.json",
    "trajectories.jsonl",
    "world.json",
    MARKER,
];

/// A staging folder for `target`, removed on drop unless committed.
#[derive(Debug)]
pub struct Staging {
    target: PathBuf,
    dir: PathBuf,
    done: bool,
}

impl Staging {
    /// Checks that `target` may be replaced and that its parent is
    /// writable, and creates the staging folder beside it.
    pub fn begin(target: &Path) -> Result<Self> {
        let name = target.file_name().ok_or_else(|| {
            Error::Input(format!("--out `{}` names no folder (give a folder name, e.g. `out`)", target.display()))
        })?;
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        check_replaceable(target)?;
        fs::create_dir_all(&parent).map_err(|source| Error::OutDir { path: parent.clone(), source })?;
        sweep_dead(&parent, &name.to_string_lossy());
        let stem = format!(".{}.tmp-{}", name.to_string_lossy(), std::process::id());
        let dir = (0..1000)
            .map(|k| parent.join(format!("{stem}-{k}")))
            .find(|d| fs::create_dir(d).is_ok())
            .ok_or_else(|| Error::OutDir {
                path: parent.clone(),
                source: fs::create_dir(parent.join(&stem))
                    .err()
                    .unwrap_or_else(|| std::io::Error::other("no free name")),
            })?;
        crate::launch::remove_on_interrupt(&dir);
        let s = Staging { target: target.to_path_buf(), dir, done: false };
        fs::write(s.dir.join(MARKER), "written by gridswarm; this folder is replaced whole by the next run\n")
            .map_err(|source| Error::Write { path: s.dir.join(MARKER), source })?;
        Ok(s)
    }

    /// Where to write the files.
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// The folder the files will end up in.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Puts the staged files in place of `target`, whose old contents are
    /// removed only once the new ones are there.
    pub fn commit(mut self) -> Result<()> {
        // A signal meanwhile ends the command after the renames, not between them.
        crate::launch::uninterrupted(|| self.put_in_place())?;
        // Renamed into place: a signal now has nothing to remove.
        crate::launch::finished(&self.dir);
        Ok(())
    }

    fn put_in_place(&mut self) -> Result<()> {
        check_replaceable(&self.target)?;
        let old = self.dir.with_extension("old");
        let had_old = self.target.exists();
        if had_old {
            fs::rename(&self.target, &old).map_err(|source| Error::OutDir { path: self.target.clone(), source })?;
        }
        if let Err(source) = fs::rename(&self.dir, &self.target) {
            if had_old {
                let _ = fs::rename(&old, &self.target);
            }
            return Err(Error::OutDir { path: self.target.clone(), source });
        }
        self.done = true;
        if had_old {
            let _ = fs::remove_dir_all(&old);
        }
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.done {
            let _ = fs::remove_dir_all(&self.dir);
            crate::launch::finished(&self.dir);
        }
    }
}

/// Removes the staging folders (and their `.old` twins) that a command
/// writing to `parent/name` left when it was killed with `kill -9`, which
/// no handler sees: `.<name>.tmp-<pid>-<k>[.old]` whose process is gone,
/// a real folder of this uid (never through a symlink) that gridswarm
/// wrote ([`is_ours`]). A folder of a live process, of another user or
/// holding anything else is left alone.
fn sweep_dead(parent: &Path, name: &str) {
    let head = format!(".{name}.tmp-");
    let Ok(entries) = fs::read_dir(parent) else { return };
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = file.strip_prefix(&head).and_then(staging_pid) else { continue };
        let path = e.path();
        let dead = pid != std::process::id() && !gridswarm::ipc::pid_alive(pid);
        if dead && gridswarm::ipc::is_own_folder(&path) && is_ours(&path) {
            let _ = fs::remove_dir_all(&path);
        }
    }
}

/// The pid of a staging folder's name after `.<name>.tmp-`: `<pid>-<k>` or `<pid>-<k>.old`.
fn staging_pid(rest: &str) -> Option<u32> {
    let (pid, k) = rest.split_once('-')?;
    let k = k.strip_suffix(".old").unwrap_or(k);
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (digits(pid) && digits(k)).then(|| pid.parse().ok()).flatten()
}

/// A folder gridswarm wrote: it holds [`MARKER`], or only files gridswarm
/// writes (none at all included).
fn is_ours(dir: &Path) -> bool {
    let ours =
        |e: &fs::DirEntry| e.file_type().is_ok_and(|t| t.is_file()) && OUR_FILES.iter().any(|f| e.file_name() == *f);
    let only_ours = fs::read_dir(dir).map(|d| d.flatten().all(|e| ours(&e))).unwrap_or(false);
    only_ours || fs::symlink_metadata(dir.join(MARKER)).is_ok_and(|m| m.is_file())
}

/// `target` is missing, an empty folder, or a folder gridswarm wrote.
fn check_replaceable(target: &Path) -> Result<()> {
    let Ok(meta) = fs::symlink_metadata(target) else { return Ok(()) };
    if !meta.is_dir() {
        return Err(Error::Input(format!("--out `{}` exists and is not a folder", target.display())));
    }
    if is_ours(target) {
        return Ok(());
    }
    Err(Error::Input(format!(
        "--out `{}` holds files gridswarm did not write; it replaces only its own output folders: \
         give a new or empty folder",
        target.display()
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("gridswarm-staging-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> =
            fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
        v.sort();
        v
    }

    #[test]
    fn a_committed_run_replaces_the_old_one_whole() {
        let d = scratch("replace");
        let out = d.join("out");
        let s = Staging::begin(&out).unwrap();
        fs::write(s.path().join("a.csv"), "1").unwrap();
        fs::write(s.path().join("old-only.txt"), "x").unwrap();
        s.commit().unwrap();
        let s = Staging::begin(&out).unwrap();
        fs::write(s.path().join("a.csv"), "2").unwrap();
        s.commit().unwrap();
        // Nothing of the first run is left beside the second's files.
        assert_eq!(names(&out), [MARKER, "a.csv"]);
        assert_eq!(fs::read_to_string(out.join("a.csv")).unwrap(), "2");
        assert_eq!(names(&d), ["out"], "no staging folder left");
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_failed_run_leaves_the_previous_results() {
        let d = scratch("fail");
        let out = d.join("out");
        let s = Staging::begin(&out).unwrap();
        fs::write(s.path().join("a.csv"), "1").unwrap();
        s.commit().unwrap();
        {
            let s = Staging::begin(&out).unwrap();
            fs::write(s.path().join("a.csv"), "half").unwrap();
            // Dropped without commit: an error part-way.
        }
        assert_eq!(fs::read_to_string(out.join("a.csv")).unwrap(), "1");
        assert_eq!(names(&d), ["out"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn folders_gridswarm_did_not_write_are_never_replaced() {
        let d = scratch("foreign");
        let mine = d.join("home");
        fs::create_dir_all(&mine).unwrap();
        fs::write(mine.join("thesis.tex"), "precious").unwrap();
        let err = Staging::begin(&mine).unwrap_err().to_string();
        assert!(err.contains("did not write"), "{err}");
        assert_eq!(fs::read_to_string(mine.join("thesis.tex")).unwrap(), "precious");
        // Output of a gridswarm from before the marker is recognised by
        // its files' names.
        let old = d.join("old");
        fs::create_dir_all(&old).unwrap();
        fs::write(old.join("results.csv"), "x").unwrap();
        Staging::begin(&old).unwrap().commit().unwrap();
        assert_eq!(names(&old), [MARKER]);
        // An empty folder is fine.
        let empty = d.join("empty");
        fs::create_dir_all(&empty).unwrap();
        Staging::begin(&empty).unwrap().commit().unwrap();
        assert!(empty.join(MARKER).is_file());
        fs::remove_dir_all(&d).unwrap();
    }

    /// Issue 23: a `kill -9`'d command's staging folders go with the next
    /// command into the same place; a live one's, or one holding a file
    /// gridswarm did not write, stay.
    #[test]
    fn a_killed_commands_staging_folders_go_with_the_next_command() {
        let d = scratch("killed");
        let out = d.join("out");
        let dead = u32::MAX - 9;
        let mk = |name: &str, file: &str| {
            let p = d.join(name);
            fs::create_dir_all(&p).unwrap();
            fs::write(p.join(file), "x").unwrap();
        };
        mk(&format!(".out.tmp-{dead}-0"), MARKER);
        mk(&format!(".out.tmp-{dead}-0.old"), "results.csv");
        mk(&format!(".out.tmp-{dead}-1"), "thesis.tex");
        mk(&format!(".out.tmp-{}-7", std::process::id()), MARKER);
        mk(&format!(".other.tmp-{dead}-0"), MARKER);
        Staging::begin(&out).unwrap().commit().unwrap();
        let mut want = [
            format!(".other.tmp-{dead}-0"),
            format!(".out.tmp-{dead}-1"),
            format!(".out.tmp-{}-7", std::process::id()),
            "out".to_string(),
        ];
        want.sort();
        assert_eq!(names(&d), want);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn an_unwritable_place_fails_before_anything_runs() {
        let d = scratch("unwritable");
        let file = d.join("file");
        fs::write(&file, "x").unwrap();
        // Its parent is a file: nothing can be created there.
        let err = Staging::begin(&file.join("out")).unwrap_err().to_string();
        assert!(err.contains("file"), "{err}");
        fs::remove_dir_all(&d).unwrap();
    }
}
