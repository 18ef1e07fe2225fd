//! At-least-once delivery over zenoh, for messages a session lost.
//!
//! A zenoh session can drop and come back (a lease that ran out while a
//! process was starved of CPU, a link that flapped). What was put into it
//! meanwhile is gone, and the world would wait on an answer to a message
//! the robot never got. So the world puts a message again while its
//! answer is missing, backing off, and a robot answers a repeat with the
//! answer it already sent, without deciding twice. Every message is one
//! chunk over zenoh, so a chunk's sequence number names its message.
//! iceoryx2 loses nothing between live processes and needs none of this.

use std::time::{Duration, Instant};

use gridswarm_robot::wire::CHUNK_HEADER;

/// The first repeat of an unanswered message: far above an answer's usual
/// delay, far below the run's patience.
pub const FIRST_REPEAT: Duration = Duration::from_secs(1);
/// Repeats back off to this.
pub const MAX_REPEAT: Duration = Duration::from_secs(8);

/// The sequence number of a chunk (`None`: shorter than its header; the
/// assembler reports it).
pub fn seq_of(chunk: &[u8]) -> Option<u64> {
    (chunk.len() >= CHUNK_HEADER).then(|| u64::from_le_bytes(chunk[..8].try_into().expect("8 bytes")))
}

/// A message the world put into a robot's inbox and has no answer to.
struct Pending {
    seq: u64,
    chunk: Vec<u8>,
    due: Instant,
    gap: Duration,
}

/// The world's side: per robot, the message awaiting an answer, and the
/// newest answer heard (older or equal ones are repeats).
#[derive(Default)]
pub struct Outstanding {
    pending: Vec<Option<Pending>>,
    heard: Vec<Option<u64>>,
    /// When to look for overdue messages next.
    next_due: Option<Instant>,
    /// Messages put again.
    pub repeats: u64,
}

impl Outstanding {
    pub fn new(robots: usize) -> Self {
        Outstanding { pending: (0..robots).map(|_| None).collect(), heard: vec![None; robots], ..Default::default() }
    }

    /// Robot `r`'s inbox got message `seq` (in one chunk) at `now`.
    pub fn posted(&mut self, r: usize, seq: u64, chunk: &[u8], now: Instant) {
        let due = now + FIRST_REPEAT;
        let p = self.pending[r].get_or_insert_with(|| Pending { seq, chunk: Vec::new(), due, gap: FIRST_REPEAT });
        p.chunk.clear();
        p.chunk.extend_from_slice(chunk);
        (p.seq, p.due, p.gap) = (seq, due, FIRST_REPEAT);
        self.next_due = Some(self.next_due.map_or(due, |d| d.min(due)));
    }

    /// Robot `r` sent message `seq`: false if it is a repeat of one heard.
    pub fn heard(&mut self, r: usize, seq: u64) -> bool {
        if self.heard[r].is_some_and(|h| seq <= h) {
            return false;
        }
        self.heard[r] = Some(seq);
        if self.pending[r].as_ref().is_some_and(|p| p.seq <= seq) {
            self.pending[r] = None;
        }
        true
    }

    /// Whether a message may be overdue at `now`.
    pub fn due(&self, now: Instant) -> bool {
        self.next_due.is_some_and(|d| now >= d)
    }

    /// Hands every message overdue at `now` to `put` again, and backs off;
    /// `put` says whether it sent it (a robot known gone hears nothing).
    pub fn repeat_due(&mut self, now: Instant, mut put: impl FnMut(usize, &[u8]) -> bool) {
        if !self.due(now) {
            return;
        }
        let mut next: Option<Instant> = None;
        for (r, p) in self.pending.iter_mut().enumerate() {
            let Some(p) = p else { continue };
            if p.due <= now {
                self.repeats += u64::from(put(r, &p.chunk));
                p.gap = (p.gap * 2).min(MAX_REPEAT);
                p.due = now + p.gap;
            }
            next = Some(next.map_or(p.due, |d| d.min(p.due)));
        }
        self.next_due = next;
    }
}

/// What a robot does with a message that came.
#[derive(Debug, PartialEq, Eq)]
pub enum Incoming<'a> {
    /// A message it has not seen: read it.
    New,
    /// The message it answered last: send this answer again.
    Answered(&'a [u8]),
    /// A repeat of a message it is done with: drop it.
    Old,
}

/// A robot's side: the newest message read, and its answer.
#[derive(Default)]
pub struct Replies {
    read: Option<u64>,
    last: Option<(u64, Vec<u8>)>,
}

impl Replies {
    /// The robot sent `chunk` (message `seq`).
    pub fn sent(&mut self, seq: u64, chunk: &[u8]) {
        let (s, c) = self.last.get_or_insert_with(|| (seq, Vec::new()));
        *s = seq;
        c.clear();
        c.extend_from_slice(chunk);
    }

    /// Message `seq` came.
    pub fn came(&mut self, seq: u64) -> Incoming<'_> {
        if self.read.is_none_or(|r| seq > r) {
            self.read = Some(seq);
            return Incoming::New;
        }
        match &self.last {
            Some((s, c)) if *s == seq => Incoming::Answered(c),
            _ => Incoming::Old,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chunk(seq: u64) -> Vec<u8> {
        let mut c = seq.to_le_bytes().to_vec();
        c.extend_from_slice(&[0, 0, 0, 0, 1, 0, 0, 0, 42]);
        c
    }

    #[test]
    fn an_unanswered_message_is_put_again_backing_off_until_answered() {
        let t0 = Instant::now();
        let mut o = Outstanding::new(3);
        o.posted(1, 7, &chunk(7), t0);
        let mut put = Vec::new();
        o.repeat_due(t0 + FIRST_REPEAT / 2, |r, c| {
            put.push((r, seq_of(c)));
            true
        });
        assert!(put.is_empty(), "not before its time");
        o.repeat_due(t0 + FIRST_REPEAT, |r, c| {
            put.push((r, seq_of(c)));
            true
        });
        assert_eq!(put, [(1, Some(7))]);
        // Backed off: the next repeat comes twice as late.
        o.repeat_due(t0 + FIRST_REPEAT * 2, |r, c| {
            put.push((r, seq_of(c)));
            true
        });
        assert_eq!(put.len(), 1);
        o.repeat_due(t0 + FIRST_REPEAT * 3, |r, c| {
            put.push((r, seq_of(c)));
            true
        });
        assert_eq!(put.len(), 2);
        assert!(o.heard(1, 7));
        o.repeat_due(t0 + Duration::from_secs(60), |r, c| {
            put.push((r, seq_of(c)));
            true
        });
        assert_eq!(put.len(), 2, "an answered message is not put again");
        assert_eq!(o.repeats, 2);
        // A robot known gone is not put to, nor counted, yet backs off.
        o.posted(2, 9, &chunk(9), t0);
        let t = t0 + FIRST_REPEAT;
        o.repeat_due(t, |_, _| false);
        let mut again = 0;
        o.repeat_due(t + FIRST_REPEAT, |_, _| {
            again += 1;
            true
        });
        assert_eq!((o.repeats, again), (2, 0));
    }

    #[test]
    fn the_gap_stops_growing_at_its_cap() {
        let t0 = Instant::now();
        let mut o = Outstanding::new(1);
        o.posted(0, 1, &chunk(1), t0);
        let mut t = t0;
        let mut times = Vec::new();
        for _ in 0..10 {
            t += MAX_REPEAT;
            o.repeat_due(t, |_, _| {
                times.push(t);
                true
            });
        }
        assert_eq!(times.len(), 10, "once capped, a repeat every MAX_REPEAT");
    }

    #[test]
    fn a_repeated_answer_is_dropped_and_a_newer_post_replaces_the_pending_one() {
        let t0 = Instant::now();
        let mut o = Outstanding::new(2);
        assert!(o.heard(0, 0), "the hello");
        o.posted(0, 3, &chunk(3), t0);
        o.posted(0, 4, &chunk(4), t0);
        assert!(o.heard(0, 4));
        assert!(!o.heard(0, 4), "the same answer twice");
        assert!(!o.heard(0, 3), "an older one");
        let mut put = 0;
        o.repeat_due(t0 + MAX_REPEAT, |_, _| {
            put += 1;
            true
        });
        assert_eq!(put, 0);
    }

    #[test]
    fn a_robot_answers_a_repeat_with_its_answer_and_never_reads_it_twice() {
        let mut r = Replies::default();
        r.sent(0, &chunk(0));
        assert_eq!(r.came(1), Incoming::New);
        r.sent(1, &chunk(1));
        assert_eq!(r.came(1), Incoming::Answered(&chunk(1)[..]));
        assert_eq!(r.came(1), Incoming::Answered(&chunk(1)[..]));
        assert_eq!(r.came(0), Incoming::Old);
        // A message lost, its repeat the first to come: read once.
        assert_eq!(r.came(5), Incoming::New);
        assert_eq!(r.came(5), Incoming::Old, "read, not answered yet");
        assert_eq!(seq_of(&[1, 2]), None);
    }
}
