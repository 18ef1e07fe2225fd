//! Fuzzing (issue 11): the scenario parser over structured mutations of
//! valid scenario files, and wire decoding (radio frames and the
//! world-agent messages) over random and mutated bytes.
//!
//! A bounded run is part of `cargo test` (proptest's default of 256 cases
//! each); `scripts/fuzz.sh` runs the same tests longer by setting
//! `PROPTEST_CASES`. A failure prints the input as one line (the mutated
//! file as an escaped string, or the bytes) and proptest keeps the seed in
//! `proptest-regressions/fuzz.txt`, which replays it first on the next run.

#[path = "common/cpu.rs"]
mod cpu;

use std::time::Duration;

use gridswarm::agreement::{Agreement, ScenarioId};
use gridswarm::map::Map;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::protocol::{self, Frame, Limits};
use gridswarm::scenario::{limits, Scenario};
use gridswarm::sim::{Listen, Motor, Note, Tick};
use gridswarm::spot::Spot;
use gridswarm::wire::{
    self, AgentOutput, Assembler, Bytes, Hello, ToAgent, ToWorld, Verdict, Wake, WireFrame, WireLimits, WireSend,
};
use proptest::prelude::*;
use toml::Value;

/// The issue's bound on reading and checking any file of at most 1 MB.
const BOUND: Duration = Duration::from_secs(5);

// ---------------------------------------------------------------- scenarios

/// Valid files to mutate: the built-ins and the reference of the docs.
fn seeds() -> Vec<String> {
    let doc = include_str!("../../docs/scenario-format.md");
    let reference = doc.split("```toml\n").nth(1).and_then(|s| s.split("```").next()).expect("reference block");
    vec![
        include_str!("../scenarios/paper.toml").to_string(),
        include_str!("../scenarios/cave.toml").to_string(),
        include_str!("../scenarios/open.toml").to_string(),
        include_str!("../scenarios/small.toml").to_string(),
        reference.to_string(),
    ]
}

/// Numbers a hostile file would try: zero, signs, the extremes of f64 and
/// i64, NaN and infinities, and values just past some limit.
const EXTREMES: &[f64] = &[
    0.0,
    -1.0,
    1e-300,
    1e-3,
    0.5,
    2.0,
    1e3,
    1e5 + 1.0,
    1e15,
    1e300,
    -1e300,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
];
const INT_EXTREMES: &[i64] = &[0, -1, 1, 2, 1000, 10_001, 100_001, 4_000_000_000, i64::MAX, i64::MIN];

#[derive(Clone, Debug)]
enum Mutation {
    /// The `pick`-th number (mod their count) becomes an extreme.
    Float {
        pick: usize,
        value: usize,
    },
    Int {
        pick: usize,
        value: usize,
    },
    /// The `pick`-th key or array element disappears.
    Delete {
        pick: usize,
    },
    /// The `pick`-th array gets its first element `times` more times.
    Repeat {
        pick: usize,
        times: usize,
    },
    /// The `pick`-th value becomes a string.
    Retype {
        pick: usize,
    },
    /// The text: a line said twice (a duplicate key), or cut short.
    DuplicateLine {
        pick: usize,
    },
    Truncate {
        at: usize,
    },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let pick = any::<usize>();
    prop_oneof![
        3 => (pick, 0..EXTREMES.len()).prop_map(|(pick, value)| Mutation::Float { pick, value }),
        2 => (pick, 0..INT_EXTREMES.len()).prop_map(|(pick, value)| Mutation::Int { pick, value }),
        2 => pick.prop_map(|pick| Mutation::Delete { pick }),
        1 => (pick, prop::sample::select(vec![1usize, 2, 100, 10_001])).prop_map(|(pick, times)| Mutation::Repeat { pick, times }),
        1 => pick.prop_map(|pick| Mutation::Retype { pick }),
        1 => pick.prop_map(|pick| Mutation::DuplicateLine { pick }),
        1 => any::<usize>().prop_map(|at| Mutation::Truncate { at }),
    ]
}

#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

/// Every value's path, parents before children.
fn paths(v: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(here.clone());
    match v {
        Value::Table(t) => {
            for (k, child) in t {
                here.push(Step::Key(k.clone()));
                paths(child, here, out);
                here.pop();
            }
        }
        Value::Array(a) => {
            for (i, child) in a.iter().enumerate() {
                here.push(Step::Index(i));
                paths(child, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

fn at<'a>(v: &'a mut Value, path: &[Step]) -> &'a mut Value {
    path.iter().fold(v, |v, s| match (v, s) {
        (Value::Table(t), Step::Key(k)) => t.get_mut(k).expect("path exists"),
        (Value::Array(a), Step::Index(i)) => &mut a[*i],
        _ => unreachable!("paths follow the value"),
    })
}

/// The `pick`-th path (mod their count) whose value satisfies `want`.
fn choose(doc: &Value, pick: usize, want: impl Fn(&Value) -> bool) -> Option<Vec<Step>> {
    let mut all = Vec::new();
    paths(doc, &mut Vec::new(), &mut all);
    let mut root = doc.clone();
    let fit: Vec<Vec<Step>> = all.into_iter().filter(|p| !p.is_empty() && want(at(&mut root, p))).collect();
    (!fit.is_empty()).then(|| fit[pick % fit.len()].clone())
}

fn mutate_value(doc: &mut Value, m: &Mutation) {
    let is_num = |v: &Value| matches!(v, Value::Float(_) | Value::Integer(_));
    match *m {
        Mutation::Float { pick, value } => {
            if let Some(p) = choose(doc, pick, is_num) {
                *at(doc, &p) = Value::Float(EXTREMES[value]);
            }
        }
        Mutation::Int { pick, value } => {
            if let Some(p) = choose(doc, pick, is_num) {
                *at(doc, &p) = Value::Integer(INT_EXTREMES[value]);
            }
        }
        Mutation::Delete { pick } => {
            if let Some(mut p) = choose(doc, pick, |_| true) {
                let last = p.pop().expect("not the root");
                match (at(doc, &p), last) {
                    (Value::Table(t), Step::Key(k)) => drop(t.remove(&k)),
                    (Value::Array(a), Step::Index(i)) => drop(a.remove(i)),
                    _ => unreachable!(),
                }
            }
        }
        Mutation::Repeat { pick, times } => {
            let non_empty = |v: &Value| matches!(v, Value::Array(a) if !a.is_empty());
            if let Some(p) = choose(doc, pick, non_empty) {
                if let Value::Array(a) = at(doc, &p) {
                    let first = a[0].clone();
                    a.extend(std::iter::repeat_n(first, times));
                }
            }
        }
        Mutation::Retype { pick } => {
            if let Some(p) = choose(doc, pick, |_| true) {
                *at(doc, &p) = Value::String("x".into());
            }
        }
        Mutation::DuplicateLine { .. } | Mutation::Truncate { .. } => {}
    }
}

fn mutate_text(text: String, m: &Mutation) -> String {
    match *m {
        Mutation::DuplicateLine { pick } => {
            let lines: Vec<&str> = text.lines().collect();
            let k = pick % lines.len().max(1);
            let mut out: Vec<&str> = lines.clone();
            if let Some(l) = lines.get(k) {
                out.insert(k, l);
            }
            out.join("\n")
        }
        Mutation::Truncate { at } => {
            let mut cut = at % (text.len() + 1);
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text[..cut].to_string()
        }
        _ => text,
    }
}

/// The seed file with the mutations applied, as a file's text; `None` when
/// the mutated value has no TOML form (an array mixing tables and strings).
fn mutated(seed: &str, ms: &[Mutation]) -> Option<String> {
    let mut doc: Value = toml::from_str(seed).expect("seeds are valid TOML");
    for m in ms {
        mutate_value(&mut doc, m);
    }
    let mut text = toml::to_string(&doc).ok()?;
    for m in ms {
        text = mutate_text(text, m);
    }
    Some(text)
}

/// Reads `text` as `gridswarm check` would; an admitted scenario's sizes
/// are within the limits, and the whole takes less than [`BOUND`].
fn check_like_the_command(text: &str) -> Result<(), TestCaseError> {
    let one_line = format!("{text:?}");
    let (checked, took) = cpu::timed(|| -> Result<(), TestCaseError> {
        if let Ok(s) = Scenario::parse(text, "fuzz.toml") {
            prop_assert!(limits::admit(&s).is_ok(), "admitted past the limits: {}", one_line);
            let w = s.world();
            prop_assert!(w.grid.len() as f64 <= limits::MAX_FRAME_VERTICES, "{}", one_line);
            if let Ok(starts) = s.start_vertices(&w, s.robots) {
                let report = gridswarm::assumptions::check(&s, &w, &starts);
                prop_assert!(!report.checks.is_empty());
            }
        }
        Ok(())
    });
    checked?;
    prop_assert!(took < BOUND, "took {:?} of CPU on {}", took, one_line);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { max_shrink_iters: 256, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenarios_are_read_or_refused_in_bounded_time(
        seed in 0usize..5,
        ms in prop::collection::vec(mutation(), 1..4),
    ) {
        let seeds = seeds();
        let text = mutated(&seeds[seed % seeds.len()], &ms);
        prop_assume!(text.is_some());
        check_like_the_command(&text.unwrap_or_default())?;
    }

    #[test]
    fn arbitrary_text_is_refused_cleanly(text in "\\PC{0,300}") {
        prop_assert!(Scenario::parse(&text, "fuzz.toml").is_err() || text.contains("[area]"));
    }
}

#[test]
fn the_seeds_are_valid_and_mutations_apply() {
    for s in seeds() {
        Scenario::parse(&s, "seed.toml").unwrap();
    }
    let seed = &seeds()[0];
    let m = Mutation::Float { pick: 0, value: 9 };
    assert_ne!(mutated(seed, &[m]), mutated(seed, &[]));
    let e = Scenario::parse(&mutated(seed, &[Mutation::Repeat { pick: 0, times: 10_001 }]).unwrap(), "x");
    assert!(e.is_err());
}

// ---------------------------------------------------------------- wire

const FRAME_LIMITS: Limits = Limits { vertices: 100, targets: 9, robots: 13 };
const WIRE_LIMITS: WireLimits = WireLimits { robots: 13, vertices: 100, targets: 9, frame_bytes: 1000, items: 50 };

fn map() -> impl Strategy<Value = Map> {
    let ids = || prop::collection::vec(0usize..100, 0..10);
    (ids(), ids(), prop::collection::vec((0usize..100, any::<u8>()), 0..10), prop::collection::vec(spot(), 0..4))
        .prop_flat_map(|(visited, known, open, targets)| {
            prop::collection::vec((0u16..13, 0u32..100, any::<u32>()), 0..3).prop_map(move |failed| {
                let mut m = Map::new(100);
                visited.iter().for_each(|&v| m.set_visited(v as u32, true));
                known.iter().for_each(|&v| m.set_known(v as u32, true));
                open.iter().for_each(|&(v, b)| m.or_open(v as u32, b));
                targets.iter().for_each(|&t| {
                    m.targets.insert(t);
                });
                for &(r, at, round) in &failed {
                    m.add_failed(r, at, round);
                }
                m
            })
        })
}

/// Any spot a laser may report.
fn spot() -> impl Strategy<Value = Spot> {
    (any::<i32>(), any::<i32>()).prop_map(|(x, y)| Spot { x, y })
}

fn robots() -> impl Strategy<Value = Vec<u16>> {
    prop::collection::vec(0u16..13, 0..6)
}

/// Any frame inside [`FRAME_LIMITS`].
fn frame() -> impl Strategy<Value = Frame> {
    let (round, from, v) = (any::<u32>, || 0u16..13, || 0u32..100);
    prop_oneof![
        (round(), from(), v(), any::<u64>(), any::<bool>(), any::<bool>(), map()).prop_map(
            |(round, from, at, sent, halted, stop, map)| Frame::Map { round, from, at, sent, halted, stop, map }
        ),
        (round(), from(), v(), v(), robots()).prop_map(|(round, from, at, next, accounted)| Frame::Choice {
            round,
            from,
            at,
            next,
            accounted
        }),
        (round(), from(), robots(), robots()).prop_map(|(round, from, acked, refused)| Frame::Ack {
            round,
            from,
            acked,
            refused
        }),
        (round(), from(), any::<bool>()).prop_map(|(round, from, moving)| Frame::Commit { round, from, moving }),
        (round(), from(), prop::collection::vec(spot(), 0..5), any::<bool>())
            .prop_map(|(round, from, targets, stop)| Frame::Flood { round, from, targets, stop }),
        (round(), from()).prop_map(|(round, from)| Frame::Wait { round, from }),
    ]
}

fn bytes(max: usize) -> impl Strategy<Value = Bytes> {
    prop::collection::vec(any::<u8>(), 0..max).prop_map(Bytes)
}

/// Any world-to-agent message inside [`WIRE_LIMITS`].
fn to_agent() -> impl Strategy<Value = ToAgent> {
    let tick = (any::<u32>(), any::<u64>(), 0u32..100, any::<u8>(), any::<u8>(), prop::collection::vec(spot(), 0..5))
        .prop_map(|(round, start, at, open, occupied, targets)| Tick { round, start, at, open, occupied, targets });
    let frames = prop::collection::vec(
        (0u16..13, any::<u64>(), bytes(200)).prop_map(|(from, at, bytes)| WireFrame { from, at, bytes }),
        0..5,
    );
    prop_oneof![
        (any::<u64>(), any::<u64>(), prop::option::of(tick), frames)
            .prop_map(|(seq, now, tick, frames)| ToAgent::Wake(Wake { seq, now, tick, frames })),
        Just(ToAgent::End),
        (any::<u64>(), prop::option::of("[ -~\\n]{0,40}"))
            .prop_map(|(nonce, refusal)| ToAgent::Verdict(Verdict { nonce, refusal })),
    ]
}

fn note() -> impl Strategy<Value = Note> {
    prop_oneof![
        (0u16..13).prop_map(|robot| Note::Declared { robot }),
        (0u16..13).prop_map(|robot| Note::Rejoined { robot }),
        (0u16..13).prop_map(|robot| Note::TimedOut { robot }),
        Just(Note::Unsure),
        (any::<bool>(), any::<bool>(), any::<bool>()).prop_map(|(ends_search, relayed, exhausted)| Note::Stopped {
            ends_search,
            relayed,
            exhausted
        }),
        Just(Note::Stale),
        Just(Note::Malformed),
    ]
}

/// A hello, its texts and one parameter as given.
fn hello(robot: u32, pid: u32, nonce: u64, seed: u64, text: &str, r_c: f64) -> ToWorld {
    let sc = Scenario::builtin("small").unwrap();
    let mut params = sc.params;
    params.r_c = r_c;
    let id = ScenarioId { name: text.into(), sha3_256: ScenarioId::of(&sc).sha3_256 };
    let cfg = gridswarm::outcome::RunConfig::new(Policy::Repulsive, seed, Situation::One);
    let mut setup = cfg.robot_setup(&sc.world(), 0, 3);
    setup.params = params;
    let agreement = Agreement::of(text, id, &setup);
    ToWorld::Hello(Box::new(Hello { agreement, robot, pid, host: text.into(), nonce }))
}

/// Any agent-to-world message inside [`WIRE_LIMITS`].
fn to_world() -> impl Strategy<Value = ToWorld> {
    let send =
        (bytes(300), any::<u64>(), any::<u8>()).prop_map(|(bytes, ready, copies)| WireSend { bytes, ready, copies });
    let motor = prop_oneof![(0u32..100).prop_map(Motor::Go), Just(Motor::Halt), Just(Motor::Resume)];
    prop_oneof![
        (any::<u32>(), any::<u32>(), any::<u64>(), any::<u64>(), "[a-z\\x00-\\x1f]{0,12}", 0.1f64..10.0)
            .prop_map(|(robot, pid, nonce, seed, text, r_c)| hello(robot, pid, nonce, seed, &text, r_c)),
        (
            any::<u64>(),
            prop::collection::vec(send, 0..4),
            prop::option::of((motor, any::<u64>())),
            prop::option::of(any::<u64>()),
            (any::<bool>(), any::<u32>(), any::<u8>(), any::<[u64; 8]>(), any::<[u64; 8]>())
                .prop_map(|(on, round, hold, except, tags)| Listen { on, round, hold, except, tags }),
            prop::collection::vec(note(), 0..5)
        )
            .prop_map(|(seq, send, motor, alarm, listen, notes)| ToWorld::Output(AgentOutput {
                seq,
                send,
                motor,
                alarm,
                listen,
                notes
            })),
    ]
}

/// A way to damage bytes: flip, cut, insert, or splice another message in.
#[derive(Clone, Debug)]
enum Damage {
    Flip(usize, u8),
    Cut(usize),
    Insert(usize, Vec<u8>),
    Varint(usize),
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        3 => (any::<usize>(), 1u8..).prop_map(|(i, b)| Damage::Flip(i, b)),
        1 => any::<usize>().prop_map(Damage::Cut),
        1 => (any::<usize>(), prop::collection::vec(any::<u8>(), 1..20)).prop_map(|(i, b)| Damage::Insert(i, b)),
        // A huge length or count where a small one was: ten 0xff bytes.
        1 => any::<usize>().prop_map(Damage::Varint),
    ]
}

fn damaged(mut b: Vec<u8>, ds: &[Damage]) -> Vec<u8> {
    for d in ds {
        let n = b.len().max(1);
        match d {
            Damage::Flip(i, x) if !b.is_empty() => b[i % n] ^= x,
            Damage::Cut(i) => b.truncate(i % n),
            Damage::Insert(i, x) => {
                let at = i % (b.len() + 1);
                b.splice(at..at, x.iter().copied());
            }
            Damage::Varint(i) => {
                let at = i % (b.len() + 1);
                b.splice(at..at, [0xff; 9].into_iter().chain([0x7f]));
            }
            Damage::Flip(..) => {}
        }
    }
    b
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

proptest! {
    #[test]
    fn valid_frames_round_trip(f in frame()) {
        prop_assert_eq!(protocol::decode(&protocol::encode(&f), &FRAME_LIMITS), Ok(f));
    }

    #[test]
    fn damaged_frames_decode_to_frames_in_range_or_fail(f in frame(), ds in prop::collection::vec(damage(), 1..4)) {
        let b = damaged(protocol::encode(&f), &ds);
        if let Ok(g) = protocol::decode(&b, &FRAME_LIMITS) {
            // What survives is inside the run's limits and reads back as itself.
            prop_assert!(protocol::check(&g, &FRAME_LIMITS).is_ok(), "bytes {}", hex(&b));
            prop_assert_eq!(protocol::decode(&protocol::encode(&g), &FRAME_LIMITS), Ok(g), "bytes {}", hex(&b));
        }
    }

    #[test]
    fn random_bytes_never_panic_any_decoder(b in prop::collection::vec(any::<u8>(), 0..2000)) {
        let _ = protocol::decode(&b, &FRAME_LIMITS);
        let _ = wire::decode_to_agent(&b, &WIRE_LIMITS);
        let _ = wire::decode_to_world(&b, &WIRE_LIMITS);
    }

    #[test]
    fn valid_messages_round_trip(a in to_agent(), w in to_world()) {
        prop_assert_eq!(wire::decode_to_agent(&wire::encode_to_agent(&a), &WIRE_LIMITS), Ok(a));
        prop_assert_eq!(wire::decode_to_world(&wire::encode_to_world(&w), &WIRE_LIMITS), Ok(w));
    }

    #[test]
    fn damaged_messages_decode_in_range_or_fail(
        a in to_agent(),
        w in to_world(),
        ds in prop::collection::vec(damage(), 1..4),
    ) {
        let b = damaged(wire::encode_to_agent(&a), &ds);
        if let Ok(m) = wire::decode_to_agent(&b, &WIRE_LIMITS) {
            prop_assert_eq!(wire::decode_to_agent(&wire::encode_to_agent(&m), &WIRE_LIMITS), Ok(m), "bytes {}", hex(&b));
        }
        let b = damaged(wire::encode_to_world(&w), &ds);
        if let Ok(m) = wire::decode_to_world(&b, &WIRE_LIMITS) {
            prop_assert_eq!(wire::decode_to_world(&wire::encode_to_world(&m), &WIRE_LIMITS), Ok(m), "bytes {}", hex(&b));
        }
    }

    #[test]
    fn chunk_streams_reassemble_only_whole_messages(
        msgs in prop::collection::vec(prop::collection::vec(any::<u8>(), 0..500), 1..5),
        max in 17usize..200,
        ds in prop::collection::vec(damage(), 0..3),
        order in prop::collection::vec(any::<usize>(), 0..6),
    ) {
        let mut chunks = Vec::new();
        for (seq, m) in msgs.iter().enumerate() {
            wire::chunks(seq as u64, m, max, |c| chunks.push(c.to_vec()));
        }
        // Swap a few chunks, damage one.
        for w in order.windows(2) {
            let n = chunks.len();
            chunks.swap(w[0] % n, w[1] % n);
        }
        if let Some(k) = order.first() {
            let n = chunks.len();
            chunks[k % n] = damaged(chunks[k % n].clone(), &ds);
        }
        let mut a = Assembler::new(400);
        for c in &chunks {
            if let Ok(Some((_, whole))) = a.push(c) {
                prop_assert!(whole.len() <= 400, "chunks {:?}", chunks.iter().map(|c| hex(c)).collect::<Vec<_>>());
            }
        }
    }
}
