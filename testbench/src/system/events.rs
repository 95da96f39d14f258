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

/// Events in clock order (ties in the order they were queued, every frame start counting as
/// queued when the first was, see [`EventQueue::push_frame_start`]).
#[derive(Default)]
pub(super) struct EventQueue {
    heap: BinaryHeap<Reverse<(u64, u64, usize)>>,
    events: Vec<Option<Event>>,
    /// The queue position of frame 0's start, once queued.
    frame_base: Option<u64>,
}

/// Queue positions kept for frame starts: a run's frames, however many.
const FRAME_POSITIONS: u64 = 1 << 48;

impl EventQueue {
    /// Queues `e` on `clock`.
    pub(super) fn push(&mut self, clock: u64, e: Event) {
        let queued = self.events.len() as u64 + self.frame_base.map_or(0, |_| FRAME_POSITIONS);
        self.insert(clock, queued, e);
    }
    /// Queues frame `k`'s start on `clock`. Each frame start is queued as the one before it
    /// comes due (a run handed its frames one at a time has no last frame to queue up to), in
    /// the place it would hold had every frame's start been queued with frame 0's: ties go
    /// as they did then.
    pub(super) fn push_frame_start(&mut self, clock: u64, k: usize) {
        let base = *self.frame_base.get_or_insert(self.events.len() as u64);
        self.insert(clock, base + k as u64, Event::FrameStart(k));
    }
    fn insert(&mut self, clock: u64, queued: u64, e: Event) {
        self.events.push(Some(e));
        self.heap.push(Reverse((clock, queued, self.events.len() - 1)));
    }
    /// The clock of the next event.
    pub(super) fn peek(&self) -> Option<u64> {
        self.heap.peek().map(|Reverse((c, _, _))| *c)
    }
    /// The next event and its clock.
    pub(super) fn pop(&mut self) -> Option<(u64, Event)> {
        let Reverse((c, _, i)) = self.heap.pop()?;
        Some((c, self.events.get_mut(i)?.take()?))
    }
}
