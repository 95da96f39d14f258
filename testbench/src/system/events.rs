//! The discrete-event queue: frame starts and message arrivals in clock order.
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Something that happens on a clock.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Event {
    /// Frame k's FVAL rises.
    FrameStart(usize),
    /// The message at the head of the link `from` -> `to` has arrived.
    MessageArrives { to: usize, from: usize },
}

/// Events in clock order (ties in the order they were queued).
#[derive(Default)]
pub(super) struct EventQueue {
    heap: BinaryHeap<Reverse<(u64, u64)>>,
    events: Vec<Option<Event>>,
}

impl EventQueue {
    /// Queues `e` on `clock`.
    pub(super) fn push(&mut self, clock: u64, e: Event) {
        self.events.push(Some(e));
        self.heap.push(Reverse((clock, self.events.len() as u64 - 1)));
    }
    /// The clock of the next event.
    pub(super) fn peek(&self) -> Option<u64> {
        self.heap.peek().map(|Reverse((c, _))| *c)
    }
    /// The next event and its clock.
    pub(super) fn pop(&mut self) -> Option<(u64, Event)> {
        let Reverse((c, i)) = self.heap.pop()?;
        Some((c, self.events.get_mut(i as usize)?.take()?))
    }
}
