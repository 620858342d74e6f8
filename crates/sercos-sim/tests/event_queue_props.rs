//! Property tests of the event queue: events come out in (time, component, sequence) order
//! whatever the insertion order, cancelled events never come out, and the same operations
//! always give the same run (DESIGN.md, Principles: "Deterministic", "Time is injected").
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use proptest::prelude::*;
use sercos_sim::event_queue::{ComponentId, EventHandle, EventQueue};
use sercos_wire::time::Instant;

/// One step of a random workload. Times are offsets from the current time, drawn from a
/// small range so that ties in time and in component are frequent.
#[derive(Debug, Clone)]
enum Op {
    Schedule { delay: u64, target: u32 },
    Pop,
    Cancel { pick: usize },
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        4 => (0u64..6, 0u32..4).prop_map(|(delay, target)| Op::Schedule { delay, target }),
        2 => Just(Op::Pop),
        1 => any::<usize>().prop_map(|pick| Op::Cancel { pick }),
    ]
}

/// A plain reference: a vector of pending (time, target, seq) searched for the minimum.
#[derive(Default)]
struct Reference {
    pending: Vec<(u64, u32, u64)>,
    now: u64,
}

impl Reference {
    fn pop(&mut self) -> Option<(u64, u32, u64)> {
        let (index, _) = self
            .pending
            .iter()
            .enumerate()
            .min_by_key(|(_, key)| **key)?;
        let key = self.pending.remove(index);
        self.now = key.0;
        Some(key)
    }
}

/// Runs the ops on a queue and returns what was observed, step by step.
fn run(ops: &[Op]) -> Vec<(u64, u32, u64)> {
    let mut queue = EventQueue::new();
    let mut handles: Vec<EventHandle> = Vec::new();
    let mut out = Vec::new();
    for op in ops {
        match *op {
            Op::Schedule { delay, target } => {
                let at = Instant::from_picos(queue.now().as_picos() + delay);
                let seq = handles.len() as u64;
                handles.push(queue.schedule(at, ComponentId(target), seq).unwrap());
            }
            Op::Pop => {
                if let Some(event) = queue.pop_next() {
                    out.push((event.time.as_picos(), event.target.0, event.payload));
                }
            }
            Op::Cancel { pick } => {
                if !handles.is_empty() {
                    let handle = handles[pick % handles.len()];
                    if let Some(payload) = queue.cancel(handle) {
                        out.push((u64::MAX, u32::MAX, payload));
                    }
                }
            }
        }
    }
    while let Some(event) = queue.pop_next() {
        out.push((event.time.as_picos(), event.target.0, event.payload));
    }
    out
}

proptest! {
    /// Whatever the insertion order, pops come in (time, component, insertion) order.
    #[test]
    fn pops_are_sorted_by_time_component_sequence(
        events in prop::collection::vec((0u64..20, 0u32..5), 0..200)
    ) {
        let mut queue = EventQueue::new();
        for (index, &(time, target)) in events.iter().enumerate() {
            queue.schedule(Instant::from_picos(time), ComponentId(target), index).unwrap();
        }
        prop_assert_eq!(queue.len(), events.len());
        let mut expected: Vec<(u64, u32, usize)> = events
            .iter()
            .enumerate()
            .map(|(index, &(time, target))| (time, target, index))
            .collect();
        expected.sort();
        let mut popped = Vec::new();
        while let Some(event) = queue.pop_next() {
            prop_assert_eq!(queue.now(), event.time);
            popped.push((event.time.as_picos(), event.target.0, event.payload));
        }
        prop_assert_eq!(popped, expected);
        prop_assert!(queue.is_empty());
    }

    /// Cancelled events never come out; the rest keep their order; cancel gives the payload
    /// back exactly once.
    #[test]
    fn cancelled_events_do_not_come_out(
        events in prop::collection::vec((0u64..20, 0u32..5, any::<bool>()), 0..200)
    ) {
        let mut queue = EventQueue::new();
        let handles: Vec<EventHandle> = events
            .iter()
            .enumerate()
            .map(|(index, &(time, target, _))| {
                queue.schedule(Instant::from_picos(time), ComponentId(target), index).unwrap()
            })
            .collect();
        for (index, &(_, _, cancel)) in events.iter().enumerate() {
            if cancel {
                prop_assert_eq!(queue.cancel(handles[index]), Some(index));
                prop_assert_eq!(queue.cancel(handles[index]), None);
                prop_assert!(!queue.is_pending(handles[index]));
            }
        }
        let mut expected: Vec<(u64, u32, usize)> = events
            .iter()
            .enumerate()
            .filter(|(_, e)| !e.2)
            .map(|(index, &(time, target, _))| (time, target, index))
            .collect();
        expected.sort();
        prop_assert_eq!(queue.len(), expected.len());
        prop_assert_eq!(queue.peek_time().map(Instant::as_picos), expected.first().map(|e| e.0));
        let mut popped = Vec::new();
        while let Some(event) = queue.pop_next() {
            popped.push((event.time.as_picos(), event.target.0, event.payload));
        }
        prop_assert_eq!(popped, expected);
    }

    /// Interleaved schedule / pop / cancel agree with a plain reference model, and
    /// peek_time always names the next event.
    #[test]
    fn interleaved_operations_match_reference(ops in prop::collection::vec(op(), 0..300)) {
        let mut queue = EventQueue::new();
        let mut reference = Reference::default();
        let mut handles: Vec<(EventHandle, (u64, u32, u64))> = Vec::new();
        for op in &ops {
            match *op {
                Op::Schedule { delay, target } => {
                    let at = reference.now + delay;
                    let seq = handles.len() as u64;
                    let handle = queue
                        .schedule(Instant::from_picos(at), ComponentId(target), seq)
                        .unwrap();
                    prop_assert_eq!(handle.sequence(), seq);
                    handles.push((handle, (at, target, seq)));
                    reference.pending.push((at, target, seq));
                }
                Op::Pop => {
                    let got = queue
                        .pop_next()
                        .map(|e| (e.time.as_picos(), e.target.0, e.payload));
                    prop_assert_eq!(got, reference.pop());
                }
                Op::Cancel { pick } => {
                    if let Some(&(handle, key)) = handles.get(pick % handles.len().max(1)) {
                        let was = reference.pending.iter().position(|k| *k == key);
                        if let Some(index) = was {
                            reference.pending.remove(index);
                        }
                        prop_assert_eq!(queue.cancel(handle), was.map(|_| key.2));
                    }
                }
            }
            prop_assert_eq!(queue.len(), reference.pending.len());
            prop_assert_eq!(
                queue.peek_time().map(Instant::as_picos),
                reference.pending.iter().min().map(|k| k.0)
            );
            prop_assert_eq!(queue.now().as_picos(), reference.now);
        }
    }

    /// The same operations give the same run, twice.
    #[test]
    fn same_operations_same_run(ops in prop::collection::vec(op(), 0..300)) {
        prop_assert_eq!(run(&ops), run(&ops));
    }
}
