//! The kernel's event queue: events in time order, ties in the order they
//! were pushed.

use std::collections::BinaryHeap;

use super::Ev;
use crate::sim::Time;

/// The event queue: a min-heap of small keys over a slab of events, so
/// that sifting moves 24 bytes, not whole events.
pub(super) struct Queue<P> {
    heap: BinaryHeap<std::cmp::Reverse<(Time, u64, u32)>>,
    slab: Vec<Option<Ev<P>>>,
    free: Vec<u32>,
    seq: u64,
}

impl<P> Queue<P> {
    pub(super) fn new() -> Self {
        Queue { heap: BinaryHeap::new(), slab: Vec::new(), free: Vec::new(), seq: 0 }
    }

    pub(super) fn push(&mut self, time: Time, ev: Ev<P>) {
        self.seq += 1;
        let k = match self.free.pop() {
            Some(k) => {
                self.slab[k as usize] = Some(ev);
                k
            }
            None => {
                self.slab.push(Some(ev));
                (self.slab.len() - 1) as u32
            }
        };
        self.heap.push(std::cmp::Reverse((time, self.seq, k)));
    }

    pub(super) fn peek_time(&self) -> Option<Time> {
        self.heap.peek().map(|e| e.0 .0)
    }

    pub(super) fn pop(&mut self) -> Option<(Time, Ev<P>)> {
        let std::cmp::Reverse((t, _, k)) = self.heap.pop()?;
        self.free.push(k);
        Some((t, self.slab[k as usize].take().expect("a queued event")))
    }

    pub(super) fn events(&self) -> impl Iterator<Item = &Ev<P>> {
        self.slab.iter().flatten()
    }
}
