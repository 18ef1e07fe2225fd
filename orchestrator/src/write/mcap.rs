//! A run in Foxglove's well-known schemas, for `--mcap FILE` and `--live`:
//! what the world lets an observer see ([`gridswarm::sim::watch`]) turned
//! into messages on a fixed set of channels of one Foxglove [`Context`].
//! Which sinks listen (an MCAP file, the live server, both) is the
//! caller's choice; this module only converts, stamps every message with
//! the simulated time, and never decides anything for the run ([`topics`]
//! reads a file back, for checks).
//!
//! Channels: [`ROBOTS`] (PosesInFrame, every robot each slot), one Grid a
//! robot under [`MAPS`] (its explored map from each map frame it sends,
//! when it changed), [`TARGETS`] (SceneUpdate: every target, green once
//! some robot's laser saw it), [`RADIO`], [`FAULTS`] and [`COLLISIONS`]
//! (JSON with a JSON schema: one message a frame, a fault, a slot) and
//! [`LOG`] (Log: faults, finds and collisions in words).

use std::rc::Rc;
use std::sync::Arc;

use foxglove::bytes::Bytes;
use foxglove::messages::{
    log::Level, packed_element_field::NumericType, Color, Grid, Log, PackedElementField, Pose, PosesInFrame,
    Quaternion, SceneEntity, SceneUpdate, SpherePrimitive, Timestamp, Vector2, Vector3,
};
use foxglove::{Channel, Context, PartialMetadata, RawChannel, Schema};
use gridswarm::grid::VertexId;
use gridswarm::protocol::{self, Frame, Limits};
use gridswarm::sim::watch::{Event, Sent, Watch};
use gridswarm::sim::{seconds, Fault, Tick, Time};
use gridswarm::world::World;
use serde_json::json;

use crate::error::{Error, Result};
use crate::live::Pace;

pub const ROBOTS: &str = "/robots";
/// Robot `k`'s map is `{MAPS}/robot_{k}`.
pub const MAPS: &str = "/maps";
pub const TARGETS: &str = "/targets";
pub const RADIO: &str = "/radio";
pub const FAULTS: &str = "/faults";
pub const COLLISIONS: &str = "/collisions";
pub const LOG: &str = "/log";
/// The frame every position is in: the scenario's own coordinates.
pub const FRAME: &str = "world";

const RADIO_SCHEMA: &str = r#"{"type":"object","properties":{
"kind":{"type":"string","enum":["map","choice","ack","commit","flood"]},
"round":{"type":"integer"},"sender":{"type":"integer"},"sent_s":{"type":"number"},
"receivers":{"type":"array","items":{"type":"integer"}},
"lost":{"type":"array","items":{"type":"integer"},"description":"robots in range that lost every copy"}}}"#;
const FAULT_SCHEMA: &str = r#"{"type":"object","properties":{
"robot":{"type":"integer"},"kind":{"type":"string","enum":["crash","freeze","thaw","slow"]},
"round":{"type":"integer"},"at_s":{"type":"number"}}}"#;
const COLLISION_SCHEMA: &str = r#"{"type":"object","properties":{
"round":{"type":"integer"},"end_s":{"type":"number"},
"collisions":{"type":"integer","description":"collisions the referee counted in the slot"}}}"#;

/// The run's channels on one context.
struct Channels {
    robots: Channel<PosesInFrame>,
    maps: Vec<Channel<Grid>>,
    targets: Channel<SceneUpdate>,
    radio: Arc<RawChannel>,
    faults: Arc<RawChannel>,
    collisions: Arc<RawChannel>,
    log: Channel<Log>,
}

fn json_channel(ctx: &Arc<Context>, topic: &str, name: &str, schema: &'static str) -> Result<Arc<RawChannel>> {
    ctx.channel_builder(topic)
        .message_encoding("json")
        .schema(Schema::new(name, "jsonschema", schema.as_bytes()))
        .build_raw()
        .map_err(|e| Error::Run(format!("cannot open the MCAP channel {topic}: {e}")))
}

impl Channels {
    fn new(ctx: &Arc<Context>, robots: usize) -> Result<Self> {
        Ok(Channels {
            robots: ctx.channel_builder(ROBOTS).build(),
            maps: (0..robots).map(|k| ctx.channel_builder(format!("{MAPS}/robot_{k}")).build()).collect(),
            targets: ctx.channel_builder(TARGETS).build(),
            radio: json_channel(ctx, RADIO, "gridswarm.RadioFrame", RADIO_SCHEMA)?,
            faults: json_channel(ctx, FAULTS, "gridswarm.Fault", FAULT_SCHEMA)?,
            collisions: json_channel(ctx, COLLISIONS, "gridswarm.Collisions", COLLISION_SCHEMA)?,
            log: ctx.channel_builder(LOG).build(),
        })
    }
}

/// Nanoseconds of simulated time (the world counts microseconds).
fn nanos(t: Time) -> u64 {
    t.saturating_mul(1000)
}

fn stamp(t: Time) -> Option<Timestamp> {
    let ns = nanos(t);
    Some(Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32))
}

fn log_json(ch: &RawChannel, t: Time, v: serde_json::Value) {
    ch.log_with_meta(v.to_string().as_bytes(), PartialMetadata { log_time: Some(nanos(t)) });
}

fn vec3(x: f64, y: f64, z: f64) -> Option<Vector3> {
    Some(Vector3 { x, y, z })
}

fn pose(x: f64, y: f64) -> Pose {
    Pose { position: vec3(x, y, 0.0), orientation: Some(Quaternion { x: 0.0, y: 0.0, z: 0.0, w: 1.0 }) }
}

/// Turns one run's observations into messages.
pub struct Recorder<'w> {
    world: &'w World,
    ch: Channels,
    raster: Raster,
    /// Which robot's laser first saw each target.
    found: Vec<Option<usize>>,
    /// Each robot's last logged map, as the grid's bytes.
    shown: Vec<Bytes>,
    pace: Option<Pace>,
}

impl<'w> Recorder<'w> {
    /// Channels on `ctx` for a run of `robots` robots, advertised at once
    /// (a live viewer subscribes to them before [`Recorder::begin`]).
    pub fn new(ctx: &Arc<Context>, world: &'w World, robots: usize) -> Result<Self> {
        let ch = Channels::new(ctx, robots)?;
        Ok(Recorder {
            world,
            ch,
            raster: Raster::new(world),
            found: vec![None; world.targets.len()],
            shown: vec![Bytes::new(); robots],
            pace: None,
        })
    }

    /// The state at time 0 (poses at `starts`, every target unfound).
    /// `pace`: keep simulated time to a speed of wall time from now on
    /// (the live view).
    pub fn begin(&mut self, starts: &[VertexId], pace: Option<Pace>) {
        self.pace = pace;
        self.poses(0, starts);
        let all: Vec<usize> = (0..self.world.targets.len()).collect();
        self.targets(0, &all);
    }

    fn poses(&self, t: Time, at: &[VertexId]) {
        let grid = &self.world.grid;
        let poses = at
            .iter()
            .map(|&v| {
                let p = grid.position(v);
                pose(p.x, p.y)
            })
            .collect();
        self.ch.robots.log_with_time(&PosesInFrame { timestamp: stamp(t), frame_id: FRAME.into(), poses }, nanos(t));
    }

    /// Targets `which` as they are now: grey unfound, green found.
    fn targets(&self, t: Time, which: &[usize]) {
        let size = self.world.params.a * 0.4;
        let entities = which
            .iter()
            .map(|&k| {
                let p = self.world.targets[k];
                let color = match self.found[k] {
                    Some(_) => Color { r: 0.1, g: 0.8, b: 0.2, a: 1.0 },
                    None => Color { r: 0.6, g: 0.6, b: 0.6, a: 1.0 },
                };
                SceneEntity {
                    timestamp: stamp(t),
                    frame_id: FRAME.into(),
                    id: format!("target {k}"),
                    spheres: vec![SpherePrimitive {
                        pose: Some(pose(p.x, p.y)),
                        size: vec3(size, size, size),
                        color: Some(color),
                    }],
                    ..Default::default()
                }
            })
            .collect();
        self.ch.targets.log_with_time(&SceneUpdate { deletions: vec![], entities }, nanos(t));
    }

    fn say(&self, t: Time, level: Level, message: String) {
        let log =
            Log { timestamp: stamp(t), level: level as i32, message, name: "gridswarm".into(), ..Default::default() };
        self.ch.log.log_with_time(&log, nanos(t));
    }

    fn map(&mut self, t: Time, robot: usize, map: &gridswarm::map::Map) {
        let data = self.raster.draw(&self.world.grid, map);
        if self.shown.get(robot).is_none_or(|s| *s == data) {
            return;
        }
        self.shown[robot] = data.clone();
        let grid = self.raster.grid(t, data);
        self.ch.maps[robot].log_with_time(&grid, nanos(t));
    }
}

impl Watch<Rc<Frame>> for Recorder<'_> {
    fn ticked(&mut self, robot: usize, tick: &Tick) {
        // The laser reads positions; the recorder, outside the robots,
        // names the world's target at each.
        let world = self.world;
        let id = |s| (0..world.targets.len()).find(|&k| world.spot(k as u32) == s);
        let fresh: Vec<usize> =
            tick.targets.iter().filter_map(|&s| id(s)).filter(|&k| self.found.get(k) == Some(&None)).collect();
        if fresh.is_empty() {
            return;
        }
        for &k in &fresh {
            self.found[k] = Some(robot);
            self.say(tick.start, Level::Info, format!("robot {robot} found target {k} in round {}", tick.round));
        }
        self.targets(tick.start, &fresh);
    }

    fn sent(&mut self, s: Sent<'_, Rc<Frame>>) {
        let f: &Frame = s.payload;
        let v = json!({
            "kind": f.kind(),
            "round": f.round(),
            "sender": s.from,
            "sent_s": seconds(s.at),
            "receivers": s.heard,
            "lost": s.lost,
        });
        log_json(&self.ch.radio, s.at, v);
        if let Frame::Map { map, .. } = f {
            self.map(s.at, s.from, map);
        }
    }

    fn fault(&mut self, at: Time, f: &Fault) {
        let v = json!({ "robot": f.robot, "kind": f.kind.name(), "round": f.round, "at_s": seconds(at) });
        log_json(&self.ch.faults, at, v);
        self.say(at, Level::Warning, format!("fault: robot {} {} in round {}", f.robot, f.kind.name(), f.round));
    }

    fn closed(&mut self, round: u32, end: Time, positions: &[VertexId], collisions: u32) {
        if let Some(p) = &self.pace {
            p.wait(end);
        }
        let v = json!({ "round": round, "end_s": seconds(end), "collisions": collisions });
        log_json(&self.ch.collisions, end, v);
        if collisions > 0 {
            self.say(end, Level::Error, format!("{collisions} collision(s) in round {round}"));
        }
        self.poses(end, positions);
    }
}

/// The lattice drawn on square cells of side `a / 2` over the area's
/// bounding box, each vertex filling the 3x3 cells around it: a vertex's
/// neighbours are `a` apart on every lattice, so the blocks meet.
struct Raster {
    origin: (f64, f64),
    cell: f64,
    columns: usize,
    rows: usize,
    /// The cell under each vertex.
    under: Vec<(usize, usize)>,
}

/// RGBA of a cell: unknown (clear), known accessible, visited.
const SHADES: [[u8; 4]; 3] = [[0, 0, 0, 0], [120, 170, 230, 110], [30, 90, 200, 200]];

impl Raster {
    fn new(world: &World) -> Self {
        let (lo, hi) = world.area.bounding_box();
        let cell = world.params.a / 2.0;
        let columns = ((hi.x - lo.x) / cell).ceil() as usize + 3;
        let rows = ((hi.y - lo.y) / cell).ceil() as usize + 3;
        let origin = (lo.x - cell, lo.y - cell);
        let under = (0..world.grid.len())
            .map(|v| {
                let p = world.grid.position(v as VertexId);
                let c = ((p.x - origin.0) / cell).floor().clamp(1.0, (columns - 2) as f64) as usize;
                let r = ((p.y - origin.1) / cell).floor().clamp(1.0, (rows - 2) as f64) as usize;
                (c, r)
            })
            .collect();
        Raster { origin, cell, columns, rows, under }
    }

    fn draw(&self, grid: &gridswarm::grid::Grid, map: &gridswarm::map::Map) -> Bytes {
        let mut data = vec![0u8; self.columns * self.rows * 4];
        for (v, &(c, r)) in self.under.iter().enumerate().take(grid.len().min(map.vertices())) {
            let v = v as VertexId;
            let shade = if map.visited(v) {
                2
            } else if map.known(v) {
                1
            } else {
                continue;
            };
            for rr in r - 1..=r + 1 {
                for cc in c - 1..=c + 1 {
                    let i = (rr * self.columns + cc) * 4;
                    // Visited wins over known where blocks overlap.
                    if data[i + 3] < SHADES[shade][3] {
                        data[i..i + 4].copy_from_slice(&SHADES[shade]);
                    }
                }
            }
        }
        Bytes::from(data)
    }

    fn grid(&self, t: Time, data: Bytes) -> Grid {
        let field =
            |name: &str, offset| PackedElementField { name: name.into(), offset, r#type: NumericType::Uint8 as i32 };
        Grid {
            timestamp: stamp(t),
            frame_id: FRAME.into(),
            pose: Some(pose(self.origin.0, self.origin.1)),
            column_count: self.columns as u32,
            cell_size: Some(Vector2 { x: self.cell, y: self.cell }),
            row_stride: (self.columns * 4) as u32,
            cell_stride: 4,
            fields: vec![field("red", 0), field("green", 1), field("blue", 2), field("alpha", 3)],
            data,
        }
    }
}

/// Every message of an MCAP file's bytes by topic, in the file's order:
/// its log time and data. For tests and tools that check a file.
pub fn topics(bytes: &[u8]) -> std::result::Result<Topics, String> {
    let mut by_topic = Topics::new();
    for m in ::mcap::MessageStream::new(bytes).map_err(|e| e.to_string())? {
        let m = m.map_err(|e| e.to_string())?;
        by_topic.entry(m.channel.topic.clone()).or_default().push((m.log_time, m.data.into_owned()));
    }
    Ok(by_topic)
}

/// Messages by topic: log time (ns) and data.
pub type Topics = std::collections::BTreeMap<String, Vec<(u64, Vec<u8>)>>;

impl Recorder<'_> {
    /// One event of a world-server's tape ([`gridswarm::sim::watch::Tape`]),
    /// its frame decoded as a robot would: `run`'s path to the same messages.
    pub fn play(&mut self, ev: Event, limits: &Limits) -> Result<()> {
        match ev {
            Event::Ticked { robot, tick } => self.ticked(robot as usize, &tick),
            Event::Sent { at, from, frame, heard, lost } => {
                let f = protocol::decode(&frame, limits)
                    .map_err(|e| Error::Run(format!("the world's tape holds a frame that does not decode: {e}")))?;
                let payload = Rc::new(f);
                self.sent(Sent { at, from: from as usize, payload: &payload, heard: &heard, lost: &lost });
            }
            Event::Fault { at, fault } => self.fault(at, &fault),
            Event::Closed { round, end, positions, collisions } => self.closed(round, end, &positions, collisions),
        }
        Ok(())
    }
}
