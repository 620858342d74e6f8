//! The event queue at the heart of the ring simulation.
//!
//! DESIGN.md, Principles: simulated time is an integer count of picoseconds ([`Instant`]) and is
//! injected, never read; the same configuration gives the same run. The queue holds events
//! addressed to components (nodes, fibres, fault injectors) and hands them out in a total,
//! deterministic order:
//!
//! 1. earlier [`Instant`] first;
//! 2. at the same instant, the lower [`ComponentId`] first;
//! 3. for the same instant and component, the event scheduled first (a sequence number).
//!
//! The order therefore depends only on what was scheduled and in which order, never on memory
//! addresses, hashing or the wall clock. Idle time is skipped: [`EventQueue::pop_next`] jumps
//! straight to the next event's time, however far away.
//!
//! Cancelling is lazy: [`EventQueue::cancel`] takes the payload out at once and leaves a stale
//! key in the heap, which is dropped when it reaches the top. Payloads live in a slot table
//! whose slots are reused, and the heap holds small fixed-size keys, so after warm-up
//! scheduling does not allocate.
//!
//! ```
//! use sercos_sim::event_queue::{ComponentId, EventQueue};
//! use sercos_wire::time::Instant;
//!
//! let mut queue = EventQueue::new();
//! let a = queue.schedule(Instant::from_picos(62_500), ComponentId(1), "bit")?;
//! queue.schedule(Instant::from_picos(62_500), ComponentId(0), "flag")?;
//! queue.cancel(a);
//! let event = queue.pop_next().expect("one event left");
//! assert_eq!((event.time.as_picos(), event.payload), (62_500, "flag"));
//! assert_eq!(queue.now(), Instant::from_picos(62_500));
//! # Ok::<(), sercos_sim::event_queue::ScheduleError>(())
//! ```

use core::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

use sercos_wire::time::Instant;

/// The component an event is addressed to: an index the simulator assigns (node, fibre,
/// fault injector …). At equal times the lower index runs first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ComponentId(pub u32);

/// Names a scheduled event so that it can be cancelled.
///
/// A handle stays unique for the life of its queue: a handle whose event has run or been
/// cancelled never names a later event, even when its slot is reused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EventHandle {
    slot: u32,
    seq: u64,
}

impl EventHandle {
    /// The sequence number: the count of events scheduled on the queue before this one.
    pub fn sequence(self) -> u64 {
        self.seq
    }
}

/// An event taken from the queue.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Event<E> {
    /// When it happens.
    pub time: Instant,
    /// Whom it is for.
    pub target: ComponentId,
    /// The handle [`EventQueue::schedule`] returned for it.
    pub handle: EventHandle,
    /// What happens.
    pub payload: E,
}

/// Why an event could not be scheduled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ScheduleError {
    /// The time lies before the current simulated time: events cannot change the past.
    #[error("event at {at_ps} ps lies before the current time {now_ps} ps")]
    InThePast {
        /// The requested time, in picoseconds.
        at_ps: u64,
        /// The queue's current time, in picoseconds.
        now_ps: u64,
    },
    /// More events are pending at once than the slot table can index (2³² − 1).
    #[error("too many pending events")]
    Full,
}

/// The ordering key kept in the heap: (time, target, sequence) and the payload's slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Key {
    time: u64,
    target: u32,
    seq: u64,
    slot: u32,
}

impl Ord for Key {
    fn cmp(&self, other: &Self) -> Ordering {
        // The slot is not part of the order: sequence numbers are unique.
        (self.time, self.target, self.seq).cmp(&(other.time, other.target, other.seq))
    }
}

impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// One payload slot: the sequence number of the event that owns it, and its payload while the
/// event is pending.
#[derive(Debug, Clone)]
struct Slot<E> {
    seq: u64,
    payload: Option<E>,
}

/// A deterministic priority queue of timed events; see the [module documentation](self).
#[derive(Debug, Clone)]
pub struct EventQueue<E> {
    heap: BinaryHeap<Reverse<Key>>,
    slots: Vec<Slot<E>>,
    free: Vec<u32>,
    next_seq: u64,
    pending: usize,
    now: Instant,
}

impl<E> Default for EventQueue<E> {
    fn default() -> Self {
        Self::new()
    }
}

impl<E> EventQueue<E> {
    /// An empty queue at time zero.
    pub fn new() -> Self {
        Self::with_capacity(0)
    }

    /// An empty queue at time zero with room for `capacity` pending events before it
    /// allocates.
    pub fn with_capacity(capacity: usize) -> Self {
        EventQueue {
            heap: BinaryHeap::with_capacity(capacity),
            slots: Vec::with_capacity(capacity),
            free: Vec::with_capacity(capacity),
            next_seq: 0,
            pending: 0,
            now: Instant::ZERO,
        }
    }

    /// The current simulated time: the time of the last event popped (zero at the start).
    pub fn now(&self) -> Instant {
        self.now
    }

    /// Pending events (cancelled ones not counted).
    pub fn len(&self) -> usize {
        self.pending
    }

    /// Whether no event is pending.
    pub fn is_empty(&self) -> bool {
        self.pending == 0
    }

    /// Schedules `payload` for `target` at `at`, which must not lie before [`now`](Self::now).
    pub fn schedule(
        &mut self,
        at: Instant,
        target: ComponentId,
        payload: E,
    ) -> Result<EventHandle, ScheduleError> {
        if at < self.now {
            return Err(ScheduleError::InThePast {
                at_ps: at.as_picos(),
                now_ps: self.now.as_picos(),
            });
        }
        let seq = self.next_seq;
        // A freed slot is reused; free slots always index the table (it never shrinks).
        let reused = self
            .free
            .pop()
            .and_then(|slot| Some((slot, self.slots.get_mut(slot as usize)?)));
        let slot = match reused {
            Some((slot, entry)) => {
                entry.seq = seq;
                entry.payload = Some(payload);
                slot
            }
            None => {
                let slot = u32::try_from(self.slots.len())
                    .ok()
                    .filter(|&slot| slot != u32::MAX)
                    .ok_or(ScheduleError::Full)?;
                self.slots.push(Slot {
                    seq,
                    payload: Some(payload),
                });
                slot
            }
        };
        self.next_seq += 1;
        self.pending += 1;
        self.heap.push(Reverse(Key {
            time: at.as_picos(),
            target: target.0,
            seq,
            slot,
        }));
        Ok(EventHandle { slot, seq })
    }

    /// Cancels a pending event and returns its payload; `None` if it has already run or been
    /// cancelled.
    pub fn cancel(&mut self, handle: EventHandle) -> Option<E> {
        let entry = self.slots.get_mut(handle.slot as usize)?;
        if entry.seq != handle.seq {
            return None;
        }
        let payload = entry.payload.take()?;
        self.free.push(handle.slot);
        self.pending -= 1;
        self.drop_stale_top();
        self.compact_if_sparse();
        Some(payload)
    }

    /// Whether the event is still pending.
    pub fn is_pending(&self, handle: EventHandle) -> bool {
        self.slots
            .get(handle.slot as usize)
            .is_some_and(|entry| entry.seq == handle.seq && entry.payload.is_some())
    }

    /// The time of the next pending event, if any.
    pub fn peek_time(&self) -> Option<Instant> {
        // Invariant: the top of the heap is never stale (see `drop_stale_top`).
        self.heap
            .peek()
            .map(|Reverse(key)| Instant::from_picos(key.time))
    }

    /// Takes the next event in (time, target, sequence) order and advances
    /// [`now`](Self::now) to its time, skipping the idle time in between.
    pub fn pop_next(&mut self) -> Option<Event<E>> {
        loop {
            let Reverse(key) = self.heap.pop()?;
            let Some(entry) = self.slots.get_mut(key.slot as usize) else {
                continue;
            };
            if entry.seq != key.seq {
                continue;
            }
            let Some(payload) = entry.payload.take() else {
                continue;
            };
            self.free.push(key.slot);
            self.pending -= 1;
            self.now = Instant::from_picos(key.time);
            self.drop_stale_top();
            return Some(Event {
                time: self.now,
                target: ComponentId(key.target),
                handle: EventHandle {
                    slot: key.slot,
                    seq: key.seq,
                },
                payload,
            });
        }
    }

    /// Takes the next event if it happens at or before `limit`; otherwise leaves the queue as
    /// it is. The simulator's `advance_to(limit)` loop.
    pub fn pop_until(&mut self, limit: Instant) -> Option<Event<E>> {
        match self.peek_time() {
            Some(time) if time <= limit => self.pop_next(),
            _ => None,
        }
    }

    /// Runs every event up to and including `limit` in order, handing each to `handler`
    /// together with the queue (so that it can schedule and cancel), then moves
    /// [`now`](Self::now) to `limit`, skipping the idle time after the last event. Stops at
    /// the handler's first error, with `now` at that event's time. Returns the events run.
    pub fn run_until<X, F>(&mut self, limit: Instant, mut handler: F) -> Result<u64, X>
    where
        F: FnMut(&mut Self, Event<E>) -> Result<(), X>,
    {
        let mut count = 0;
        while let Some(event) = self.pop_until(limit) {
            count += 1;
            handler(self, event)?;
        }
        self.advance_to(limit);
        Ok(count)
    }

    /// Moves [`now`](Self::now) forward to `time` without running anything; does nothing if
    /// `time` is not later than now or lies after the next pending event (events are never
    /// skipped). Returns whether the time moved.
    pub fn advance_to(&mut self, time: Instant) -> bool {
        let before_next = self.peek_time().is_none_or(|next| time <= next);
        if time > self.now && before_next {
            self.now = time;
            true
        } else {
            false
        }
    }

    /// Drops every pending event; the time stays where it is.
    pub fn clear(&mut self) {
        self.heap.clear();
        self.free.clear();
        for (index, entry) in self.slots.iter_mut().enumerate() {
            entry.payload = None;
            if let Ok(slot) = u32::try_from(index) {
                self.free.push(slot);
            }
        }
        // Reuse low slots first, which keeps runs identical whatever came before.
        self.free.reverse();
        self.pending = 0;
    }

    /// Rebuilds the heap without cancelled keys once they outnumber the pending events, so
    /// that cancelling many far-away events does not grow the heap without bound.
    fn compact_if_sparse(&mut self) {
        if self.heap.len() > 2 * self.pending + 64 {
            let slots = &self.slots;
            self.heap.retain(|Reverse(key)| {
                slots
                    .get(key.slot as usize)
                    .is_some_and(|entry| entry.seq == key.seq && entry.payload.is_some())
            });
        }
    }

    /// Removes cancelled keys from the top of the heap so that [`peek_time`](Self::peek_time)
    /// sees a live event.
    fn drop_stale_top(&mut self) {
        while let Some(Reverse(key)) = self.heap.peek() {
            let live = self
                .slots
                .get(key.slot as usize)
                .is_some_and(|entry| entry.seq == key.seq && entry.payload.is_some());
            if live {
                break;
            }
            self.heap.pop();
        }
    }
}
