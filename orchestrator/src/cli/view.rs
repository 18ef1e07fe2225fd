//! `--mcap FILE`, `--live [ADDR]` and `--speed` on `simulate` and `run`:
//! the flags, and a run watched by the sinks they ask for (an MCAP file,
//! the live server, both on one Foxglove context that
//! [`crate::mcap::Recorder`] fills). `simulate` hands the recorder to the
//! in-process world; `run` follows the world-server's tape while the
//! processes run.

use std::fs::File;
use std::io::{BufWriter, Read};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use clap::Args;
use foxglove::{Context, McapWriterHandle};
use gridswarm::grid::VertexId;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::policy::Policy;
use gridswarm::protocol::Limits;
use gridswarm::sim::watch::read_event;
use gridswarm::world::World;

use crate::contract;
use crate::error::{Error, Result};
use crate::live::{self, Live, Pace, Speed};
use crate::mcap::Recorder;

#[derive(Args, Clone, Debug, Default, PartialEq)]
pub struct ViewFlags {
    /// Write the run as MCAP (Foxglove's well-known schemas, simulated time stamps) to FILE.
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Serve the run live to Foxglove over WebSocket at ADDR [default: 127.0.0.1:8765]; the
    /// run starts once a viewer subscribes to a channel.
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = live::DEFAULT_ADDR,
          value_parser = live::parse_addr)]
    pub live: Option<SocketAddr>,
    /// Simulated seconds per wall second of the live view, e.g. 10x [default: 1x].
    #[arg(long, requires = "live")]
    pub speed: Option<Speed>,
}

/// What the flags opened.
struct Sinks {
    ctx: Arc<Context>,
    mcap: Option<(PathBuf, McapWriterHandle<BufWriter<File>>)>,
    live: Option<Live>,
    speed: Speed,
}

impl ViewFlags {
    pub fn any(&self) -> bool {
        self.mcap.is_some() || self.live.is_some()
    }

    /// Usage errors before anything runs: the views need the radio's frames.
    pub fn check(&self, policy: Policy) -> Result<()> {
        if self.any() && !policy.on_grid() {
            return Err(Error::Usage(format!(
                "--mcap and --live show a grid policy's robots and radio; {} has no radio",
                policy.name()
            )));
        }
        Ok(())
    }

    /// The file created, the server started and a viewer waited for.
    fn open(&self) -> Result<Sinks> {
        let ctx = Context::new();
        let mcap = match &self.mcap {
            Some(path) => {
                let file = File::create(path).map_err(Error::write(path))?;
                let w = ctx.mcap_writer().create(BufWriter::new(file)).map_err(|e| mcap_error(path, e))?;
                Some((path.clone(), w))
            }
            None => None,
        };
        let live = self.live.map(|addr| Live::start(&ctx, addr)).transpose()?;
        Ok(Sinks { ctx, mcap, live, speed: self.speed.unwrap_or_default() })
    }

    /// `simulate`: one in-process search watched by the sinks asked for;
    /// the files it wrote.
    pub fn run(&self, world: &World, starts: &[VertexId], cfg: &RunConfig) -> Result<(RunResult, Vec<PathBuf>)> {
        let sinks = self.open()?;
        let mut recorder = sinks.recorder(world, starts)?;
        let result = contract::run_grid_watched(world, starts, cfg, &mut recorder);
        drop(recorder);
        Ok((result, sinks.close()?))
    }

    /// `run`: `go` runs the processes while the world-server writes its
    /// tape at `tape`; the tape is followed into the sinks meanwhile, to
    /// its end after `go` returns. What `go` returned, and the files written.
    pub fn watching<T>(
        &self,
        world: &World,
        starts: &[VertexId],
        tape: &Path,
        go: impl FnOnce() -> Result<T>,
    ) -> Result<(T, Vec<PathBuf>)> {
        let sinks = self.open()?;
        let mut recorder = sinks.recorder(world, starts)?;
        let done = AtomicBool::new(false);
        let limits = Limits { vertices: world.grid.len(), targets: world.targets.len(), robots: starts.len() };
        let (ran, followed) = std::thread::scope(|s| {
            let follower = s.spawn(|| follow(tape, &done, &mut recorder, &limits));
            let ran = go();
            done.store(true, Ordering::Release);
            (ran, follower.join().unwrap_or_else(|_| Err(Error::Run("the tape's reader panicked".into()))))
        });
        drop(recorder);
        let written = sinks.close()?;
        let ran = ran?;
        followed?;
        Ok((ran, written))
    }
}

impl Sinks {
    /// The recorder's channels made, a live viewer waited for, the state at time 0 logged.
    fn recorder<'w>(&self, world: &'w World, starts: &[VertexId]) -> Result<Recorder<'w>> {
        let mut recorder = Recorder::new(&self.ctx, world, starts.len())?;
        if let Some(l) = &self.live {
            eprintln!(
                "live view at ws://{}: in Foxglove, Open connection > Foxglove WebSocket; \
                 the run starts when a panel subscribes to a channel",
                l.addr
            );
            l.wait_for_viewer();
        }
        recorder.begin(starts, self.live.as_ref().map(|_| Pace::new(self.speed)));
        Ok(recorder)
    }

    /// The live server stopped once its messages are out, the file closed.
    fn close(self) -> Result<Vec<PathBuf>> {
        if let Some(l) = self.live {
            l.finish();
        }
        let mut written = Vec::new();
        if let Some((path, w)) = self.mcap {
            w.close().map_err(|e| mcap_error(&path, e))?;
            written.push(path);
        }
        Ok(written)
    }
}

fn mcap_error(path: &Path, e: foxglove::FoxgloveError) -> Error {
    Error::Run(format!("cannot write `{}`: {e}", path.display()))
}

/// Reads the tape at `path` as the world-server writes it, into `recorder`,
/// until `done` is set and the tape holds nothing more.
fn follow(path: &Path, done: &AtomicBool, recorder: &mut Recorder, limits: &Limits) -> Result<()> {
    let bad = |m: String| Error::Read { path: path.to_path_buf(), message: m };
    let mut file = None;
    let mut buf = Vec::new();
    let mut at = 0;
    loop {
        // Read after looking at `done`: whatever was written before it is read.
        let last = done.load(Ordering::Acquire);
        if file.is_none() {
            file = File::open(path).ok();
        }
        if let Some(f) = file.as_mut() {
            f.read_to_end(&mut buf).map_err(|e| bad(e.to_string()))?;
        }
        let mut any = false;
        while let Some(next) = read_event(&buf[at..]) {
            let (ev, n) = next.map_err(|e| bad(format!("a record that does not decode: {e}")))?;
            recorder.play(ev, limits)?;
            at += n;
            any = true;
        }
        buf.drain(..at);
        at = 0;
        if last {
            return Ok(());
        }
        if !any {
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}
