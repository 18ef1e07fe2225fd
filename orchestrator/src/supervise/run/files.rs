//! The files one run hands its children: the world's run file and one
//! setup per robot, in a temporary directory named after the run's
//! iceoryx2 prefix (`gridswarm-<prefix>/`), with the world's report and the
//! agents' log. The directory goes when the run ends, whatever ends it;
//! [`sweep_stale`] removes those of runs whose orchestrator was killed.

use std::fs;
use std::os::unix::fs::DirBuilderExt;
use std::path::{Path, PathBuf};

use gridswarm::agreement::ScenarioId;
use gridswarm::ipc::{self, RunFile};
use gridswarm::outcome::RunConfig;
use gridswarm::setup::SetupFile;
use gridswarm::world::World;

use crate::error::{Error, Result};

/// The run's temporary directory; removed on drop.
pub struct RunFiles {
    pub dir: PathBuf,
}

impl RunFiles {
    pub fn create(prefix: &str) -> Result<Self> {
        let dir = std::env::temp_dir().join(format!("gridswarm-{prefix}"));
        // Only this user may read the run's files (SECURITY.md).
        fs::DirBuilder::new().mode(0o700).create(&dir).map_err(Error::write(&dir))?;
        crate::launch::remove_on_interrupt(&dir);
        Ok(RunFiles { dir })
    }

    pub fn run_file(&self) -> PathBuf {
        self.dir.join("run.json")
    }

    pub fn report(&self) -> PathBuf {
        self.dir.join("report.json")
    }

    pub fn world_log(&self) -> PathBuf {
        self.dir.join("world.log")
    }

    pub fn agent_log(&self) -> PathBuf {
        self.dir.join("agents.log")
    }

    pub fn setup(&self, robot: usize) -> PathBuf {
        self.dir.join(format!("robot-{robot}.json"))
    }

    /// Writes the world's run file and every robot's setup, with the run
    /// key and scenario id its agent presents beside it.
    pub fn write(&self, run: &RunFile, world: &World, cfg: &RunConfig, (key, id): (&str, &ScenarioId)) -> Result<()> {
        write_json(&self.run_file(), run)?;
        for k in 0..run.robots {
            let setup = cfg.robot_setup(world, k, run.robots);
            let file = SetupFile { key: key.to_string(), scenario: id.clone(), setup };
            write_json(&self.setup(k), &file)?;
        }
        Ok(())
    }
}

fn write_json(path: &Path, v: &impl serde::Serialize) -> Result<()> {
    let text = serde_json::to_string(v).map_err(|e| Error::Run(format!("cannot encode {}: {e}", path.display())))?;
    fs::write(path, text).map_err(Error::write(path))
}

impl Drop for RunFiles {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.dir);
        crate::launch::finished(&self.dir);
    }
}

/// The orchestrator's own temporary files of a run (`gridswarm-<prefix>...`).
pub fn temp_files(prefix: &str) -> Vec<PathBuf> {
    let head = format!("gridswarm-{prefix}");
    fs::read_dir(std::env::temp_dir())
        .map(|d| d.flatten().filter(|e| e.file_name().to_string_lossy().starts_with(&head)).map(|e| e.path()).collect())
        .unwrap_or_default()
}

/// Removes the temporary directories of runs whose orchestrator is gone:
/// only real folders of this uid (never a symlink, never another user's
/// entry under a run's name), one listing of the temporary directory.
pub fn sweep_stale() {
    let Ok(dir) = fs::read_dir(std::env::temp_dir()) else { return };
    for e in dir.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix("gridswarm-") else { continue };
        let Some(end) = rest.find('_') else { continue };
        let Some(owner) = ipc::prefix_owner(&rest[..=end]) else { continue };
        if owner != std::process::id() && !ipc::pid_alive(owner) && ipc::is_own_folder(&e.path()) {
            let _ = fs::remove_dir_all(e.path());
        }
    }
}

/// Free and total bytes of the file system under `/dev/shm`.
fn shm_space() -> Option<(u64, u64)> {
    let path = std::ffi::CString::new("/dev/shm").ok()?;
    // SAFETY: an all-zero statvfs is a valid out-parameter for statvfs(3).
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: a valid C string and out-parameter.
    if unsafe { libc::statvfs(path.as_ptr(), &mut st) } != 0 {
        return None;
    }
    let block = st.f_frsize as u64;
    Some((st.f_bavail as u64 * block, st.f_blocks as u64 * block))
}

/// Below this much free space in `/dev/shm` a failed run says so: a run's
/// shared-memory files and pages may not have fit.
const SHM_FULL_BYTES: u64 = 1 << 20;

/// What to add to the error of a process that `died_of_sigbus` or failed,
/// measured before the run's files are removed: shared memory that ran
/// out (a page of a file in a full `/dev/shm` is a SIGBUS when touched;
/// a file that does not fit, iceoryx2's "could not be created").
pub fn shm_note(died_of_sigbus: bool) -> String {
    let Some((free, total)) = shm_space() else { return String::new() };
    let kib = |b: u64| b / 1024;
    if died_of_sigbus {
        format!(
            "; SIGBUS: the run's shared memory in /dev/shm could not be backed ({} KiB free of {} KiB): free some, or enlarge /dev/shm",
            kib(free),
            kib(total)
        )
    } else if free < SHM_FULL_BYTES {
        // Measured after the failed process removed what it had made.
        format!(
            "; /dev/shm, where the run's shared memory lives, has only {} KiB free of {} KiB: free some, or enlarge it",
            kib(free),
            kib(total)
        )
    } else {
        String::new()
    }
}
