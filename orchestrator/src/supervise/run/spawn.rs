//! The run's processes: the world-server, then one robot-agent per robot.
//! Every child is spawned with [`launch::guard`] (killed with the
//! orchestrator, in its own process group) before this process creates
//! any iceoryx2 resource (it never does), and everything it started is
//! killed, reaped and its iceoryx2 files removed on every exit path
//! ([`Processes::abort`], also on drop).

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
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
    /// Where the agents' stderr goes.
    agent_log: Option<PathBuf>,
}

impl Processes {
    pub fn new(prefix: &str, root: PathBuf) -> Self {
        Processes {
            world: None,
            world_in: None,
            agents: Vec::new(),
            prefix: prefix.to_string(),
            root,
            world_log: None,
            agent_log: None,
        }
    }

    pub fn world_pid(&self) -> u32 {
        self.world.as_ref().map_or(0, Child::id)
    }

    /// Starts the world-server; its stdout lines go to `tx`, its stderr
    /// to the run's world log ([`Processes::world_said`]).
    pub fn start_world(&mut self, bin: &Path, files: &RunFiles, tx: Sender<Event>, extra: &[String]) -> Result<()> {
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
            .args(extra)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(log);
        // It removes the run's files on SIGTERM: after a kill -9 of this
        // process, nobody else would until the next run.
        launch::guard(&mut cmd, libc::SIGTERM);
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
    pub fn start_agents(&mut self, bin: &Path, files: &RunFiles, robots: usize, extra: &[String]) -> Result<()> {
        let log_path = files.agent_log();
        let log = fs::File::create(&log_path).map_err(Error::write(&log_path))?;
        self.agent_log = Some(log_path.clone());
        let world_pid = self.world_pid();
        for i in 0..robots {
            let mut cmd = Command::new(bin);
            cmd.arg("--prefix")
                .arg(&self.prefix)
                .arg("--setup")
                .arg(files.setup(i))
                .arg("--world-pid")
                .arg(world_pid.to_string())
                .args(extra)
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(log.try_clone().map_err(Error::write(&log_path))?);
            launch::guard(&mut cmd, libc::SIGKILL);
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

    /// The first agent found to have exited with an error status (neither
    /// 0, `End`, nor [`ipc::EXIT_WORLD_GONE`]; a signal is a fault or a
    /// death the world finds by itself): its number and how it ended.
    pub fn failed_agent(&mut self) -> Option<(usize, ExitStatus)> {
        self.agents.iter_mut().enumerate().find_map(|(k, c)| match c.try_wait() {
            Ok(Some(st)) if st.code().is_some_and(|c| c != 0 && c != ipc::EXIT_WORLD_GONE) => Some((k, st)),
            _ => None,
        })
    }

    /// What agent `k` said: its own line in the agents' log (ours start
    /// `robot-agent K`), else the log's first line (another program's).
    pub fn agent_said(&self, k: usize) -> Option<String> {
        let text = self.agent_log.as_ref().and_then(|p| fs::read_to_string(p).ok()).unwrap_or_default();
        let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
        let own = format!("robot-agent {k}:");
        text.lines().find(|l| l.starts_with(&own)).or_else(|| lines.next()).map(str::to_string)
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
