//! The live view (`--live [ADDR]`, `--speed 10x`): the Foxglove WebSocket
//! server on a run's context ([`crate::mcap`] fills its channels), the
//! wait for a viewer before the run starts, and the pace that keeps
//! simulated time to a multiple of wall time. It serves; it never changes
//! what the run does, only when the command's thread goes on.

use std::net::SocketAddr;
use std::str::FromStr;
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use foxglove::websocket::{ChannelView, Client, ServerListener};
use foxglove::{Context, WebSocketServer, WebSocketServerHandle};
use gridswarm::sim::{seconds, Time};

use crate::error::{Error, Result};

/// Where `--live` serves without an address (Foxglove's default port).
pub const DEFAULT_ADDR: &str = "127.0.0.1:8765";

/// How many simulated seconds go by in one wall second (`--speed 10x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Speed(pub f64);

impl Default for Speed {
    fn default() -> Self {
        Speed(1.0)
    }
}

impl FromStr for Speed {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let n = s.strip_suffix(['x', 'X']).unwrap_or(s);
        match n.parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => Ok(Speed(v)),
            _ => Err(format!(
                "invalid speed `{s}`: expected a positive multiple of real time such as `10x`, `1x` or `0.5x`"
            )),
        }
    }
}

/// Keeps the run's simulated clock at `speed` times the wall clock from
/// when it was made.
pub struct Pace {
    start: Instant,
    speed: f64,
}

impl Pace {
    pub fn new(speed: Speed) -> Self {
        Pace { start: Instant::now(), speed: speed.0 }
    }

    /// Sleeps until simulated time `t` is due.
    pub fn wait(&self, t: Time) {
        let due = self.start + Duration::from_secs_f64(seconds(t) / self.speed);
        if let Some(d) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(d);
        }
    }
}

/// Set once a viewer subscribes to a channel (Foxglove subscribes to what its panels show).
#[derive(Default)]
struct Watched {
    seen: Mutex<bool>,
    cv: Condvar,
}

impl ServerListener for Watched {
    fn on_subscribe(&self, _client: Client, _channel: ChannelView) {
        *self.seen.lock().unwrap_or_else(|e| e.into_inner()) = true;
        self.cv.notify_all();
    }
}

/// A running live server.
pub struct Live {
    server: WebSocketServerHandle,
    watched: Arc<Watched>,
    pub addr: SocketAddr,
}

/// `ADDR` of `--live`: `HOST:PORT` with a numeric host (port 0: any free port).
pub fn parse_addr(s: &str) -> std::result::Result<SocketAddr, String> {
    s.parse::<SocketAddr>().map_err(|_| {
        format!("invalid --live address `{s}`: expected IP:PORT such as `{DEFAULT_ADDR}` or `0.0.0.0:8765`")
    })
}

impl Live {
    /// Serves `ctx`'s channels at `addr`.
    pub fn start(ctx: &Arc<Context>, addr: SocketAddr) -> Result<Self> {
        let watched = Arc::new(Watched::default());
        let server = WebSocketServer::new()
            .context(ctx)
            .name("gridswarm")
            .bind(addr.ip().to_string(), addr.port())
            .listener(watched.clone())
            .start_blocking()
            .map_err(|e| Error::Run(format!("cannot serve the live view at {addr}: {e}")))?;
        let addr = SocketAddr::new(addr.ip(), server.port());
        Ok(Live { server, watched, addr })
    }

    /// Blocks until a viewer subscribes to a channel: a run nobody
    /// watches would be over before Foxglove connects.
    pub fn wait_for_viewer(&self) {
        let mut seen = self.watched.seen.lock().unwrap_or_else(|e| e.into_inner());
        while !*seen {
            seen = self.watched.cv.wait(seen).unwrap_or_else(|e| e.into_inner());
        }
    }

    /// Stops serving once what was logged has gone out.
    pub fn finish(self) {
        self.server.stop().wait_blocking();
    }
}
