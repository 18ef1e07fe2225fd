//! The run's processes: the world-server, then one robot-agent per robot.
//! Every child is spawned with [`launch::guard`] (killed with the
//! orchestrator, in its own process group) before this process creates
//! any iceoryx2 resource (it never does), and everything it started is
//! killed, reaped and its iceoryx2 files removed on every exit path
//! ([`Processes::abort`], also on drop).

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::Sender;

use gridswarm::ipc;

use super::files::RunFiles;
use crate::error::{Error, Result};
use crate::launch::{self, Event};

/// Everything the run started, so every exit path can end it.
pub struct Processes {
    pub world: Option<Child>,
    world_in: Option<ChildStdin>,
    pub agents: Vec<Child>,
    prefix: String,
    pub root: PathBuf,
    /// Where the world-server's stderr goes.
    world_log: Option<PathBuf>,
}

impl Processes {
    pub fn new(prefix: &str, root: PathBuf) -> Self {
        Processes { world: None, world_in: None, agents: Vec::new(), prefix: prefix.to_string(), root, world_log: None }
    }

    pub fn world_pid(&self) -> u32 {
        self.world.as_ref().map_or(0, Child::id)
    }

    /// Starts the world-server; its stdout lines go to `tx`, its stderr
    /// to the run's world log ([`Processes::world_said`]).
    pub fn start_world(&mut self, bin: &Path, files: &RunFiles, tx: Sender<Event>) -> Result<()> {
        let log_path = files.world_log();
        let log = fs::File::create(&log_path).map_err(Error::write(&log_path))?;
        self.world_log = Some(log_path);
        let mut cmd = Command::new(bin);
        cmd.arg("--prefix")
            .arg(&self.prefix)
            .arg("--run")
            .arg(files.run_file())
            .arg("--report")
            .arg(files.report())
            .arg("--progress")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(log);
        launch::guard(&mut cmd);
        let mut child =
            cmd.spawn().map_err(|e| Error::Run(format!("cannot start {}: {e}", bin.display())))?;
        self.world_in = child.stdin.take();
        if let Some(out) = child.stdout.take() {
            launch::read_lines(out, tx);
        }
        self.world = Some(child);
        Ok(())
    }

    /// Starts robot-agent `0..robots`, their stderr into the run's log.
    pub fn start_agents(&mut self, bin: &Path, files: &RunFiles, robots: usize) -> Result<()> {
        let log_path = files.agent_log();
        let log = fs::File::create(&log_path).map_err(Error::write(&log_path))?;
        let world_pid = self.world_pid();
        for i in 0..robots {
            let mut cmd = Command::new(bin);
            cmd.arg("--prefix")
                .arg(&self.prefix)
                .arg("--setup")
                .arg(files.setup(i))
                .arg("--world-pid")
                .arg(world_pid.to_string())
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(log.try_clone().map_err(Error::write(&log_path))?);
            launch::guard(&mut cmd);
            let child = cmd.spawn().map_err(|e| Error::Run(format!("cannot start robot-agent {i}: {e}")))?;
            self.agents.push(child);
        }
        Ok(())
    }

    /// The lines the world-server wrote to its stderr so far.
    pub fn world_said(&self) -> Vec<String> {
        let text = self.world_log.as_ref().and_then(|p| fs::read_to_string(p).ok()).unwrap_or_default();
        text.lines().filter(|l| !l.trim().is_empty()).map(str::to_string).collect()
    }

    /// Tells the paused world to go on; false if it is gone.
    pub fn go(&mut self) -> bool {
        self.world_in.as_mut().is_some_and(|w| writeln!(w, "go").and_then(|()| w.flush()).is_ok())
    }

    /// Kills and reaps every child, removes the run's iceoryx2 files.
    pub fn abort(&mut self) {
        self.world_in = None;
        if let Some(w) = self.world.as_mut() {
            let _ = w.kill();
            let _ = w.wait();
        }
        launch::kill_and_reap(&mut self.agents);
        self.cleanup();
    }

    pub fn cleanup(&mut self) {
        let _ = ipc::cleanup_run(&self.prefix, &self.root);
    }
}

impl Drop for Processes {
    fn drop(&mut self) {
        // Whatever path left the run (an error, a panic), nothing outlives it.
        self.abort();
    }
}
