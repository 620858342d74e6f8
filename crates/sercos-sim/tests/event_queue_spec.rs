//! Example tests of the event queue's rules (DESIGN.md, Principles: time is an integer count
//! of picoseconds, injected; idle time is skipped; deterministic).
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use sercos_sim::event_queue::{ComponentId, EventQueue, ScheduleError};
use sercos_wire::time::{BitRate, Duration, Instant};

#[test]
fn idle_time_is_skipped_to_the_next_event() {
    let mut queue = EventQueue::new();
    // One bit at 16 Mbit/s is 62.5 ns: not a whole number of nanoseconds (DESIGN.md).
    let bit = BitRate::Mbit16.bit_time();
    let far = Instant::ZERO.saturating_add(Duration::from_secs(3600));
    queue.schedule(far, ComponentId(0), "late").unwrap();
    queue
        .schedule(Instant::ZERO.saturating_add(bit), ComponentId(0), "bit")
        .unwrap();
    let first = queue.pop_next().unwrap();
    assert_eq!(first.time.as_picos(), 62_500);
    let second = queue.pop_next().unwrap();
    assert_eq!((second.time, second.payload), (far, "late"));
    assert_eq!(queue.now(), far);
    assert!(queue.pop_next().is_none());
}

#[test]
fn ties_go_to_the_lower_component_then_the_earlier_schedule() {
    let mut queue = EventQueue::new();
    let t = Instant::from_picos(1000);
    queue.schedule(t, ComponentId(7), "c7 first").unwrap();
    queue.schedule(t, ComponentId(2), "c2 first").unwrap();
    queue.schedule(t, ComponentId(7), "c7 second").unwrap();
    queue.schedule(t, ComponentId(2), "c2 second").unwrap();
    let order: Vec<&str> = std::iter::from_fn(|| queue.pop_next().map(|e| e.payload)).collect();
    assert_eq!(order, ["c2 first", "c2 second", "c7 first", "c7 second"]);
}

#[test]
fn scheduling_in_the_past_is_refused() {
    let mut queue = EventQueue::new();
    queue
        .schedule(Instant::from_picos(500), ComponentId(0), ())
        .unwrap();
    queue.pop_next().unwrap();
    assert_eq!(
        queue.schedule(Instant::from_picos(499), ComponentId(0), ()),
        Err(ScheduleError::InThePast {
            at_ps: 499,
            now_ps: 500
        })
    );
    // "Now" itself is allowed: an event may schedule another at the same instant.
    assert!(
        queue
            .schedule(Instant::from_picos(500), ComponentId(0), ())
            .is_ok()
    );
}

#[test]
fn a_stale_handle_does_not_cancel_the_event_that_reuses_its_slot() {
    let mut queue = EventQueue::new();
    let old = queue
        .schedule(Instant::from_picos(10), ComponentId(0), "old")
        .unwrap();
    assert_eq!(queue.pop_next().unwrap().payload, "old");
    let new = queue
        .schedule(Instant::from_picos(20), ComponentId(0), "new")
        .unwrap();
    assert_ne!(old, new);
    assert_eq!(queue.cancel(old), None);
    assert!(queue.is_pending(new));
    assert_eq!(queue.pop_next().unwrap().payload, "new");
}

#[test]
fn cancelling_the_next_event_moves_peek_time() {
    let mut queue = EventQueue::new();
    let first = queue
        .schedule(Instant::from_picos(10), ComponentId(0), 1)
        .unwrap();
    queue
        .schedule(Instant::from_picos(30), ComponentId(0), 2)
        .unwrap();
    assert_eq!(queue.peek_time(), Some(Instant::from_picos(10)));
    assert_eq!(queue.cancel(first), Some(1));
    assert_eq!(queue.peek_time(), Some(Instant::from_picos(30)));
    assert_eq!(queue.len(), 1);
}

#[test]
fn many_cancellations_keep_the_order() {
    // Enough cancelled keys to trigger the heap's compaction.
    let mut queue = EventQueue::with_capacity(16);
    let handles: Vec<_> = (0..1000u64)
        .map(|i| {
            queue
                .schedule(Instant::from_picos(1000 - i), ComponentId(0), i)
                .unwrap()
        })
        .collect();
    for (i, handle) in handles.iter().enumerate() {
        if i % 10 != 0 {
            assert_eq!(queue.cancel(*handle), Some(i as u64));
        }
    }
    let left: Vec<u64> = std::iter::from_fn(|| queue.pop_next().map(|e| e.payload)).collect();
    let expected: Vec<u64> = (0..1000).rev().filter(|i| i % 10 == 0).collect();
    assert_eq!(left, expected);
}

#[test]
fn pop_until_stops_at_the_limit() {
    let mut queue = EventQueue::new();
    for t in [100u64, 200, 300] {
        queue
            .schedule(Instant::from_picos(t), ComponentId(0), t)
            .unwrap();
    }
    let limit = Instant::from_picos(200);
    let got: Vec<u64> = std::iter::from_fn(|| queue.pop_until(limit).map(|e| e.payload)).collect();
    assert_eq!(got, [100, 200]);
    assert_eq!(queue.len(), 1);
    // advance_to never jumps over a pending event.
    assert!(!queue.advance_to(Instant::from_picos(301)));
    assert!(queue.advance_to(Instant::from_picos(250)));
    assert_eq!(queue.now(), Instant::from_picos(250));
}

#[test]
fn clear_drops_everything_and_keeps_time() {
    let mut queue = EventQueue::new();
    queue
        .schedule(Instant::from_picos(5), ComponentId(0), 'a')
        .unwrap();
    queue.pop_next().unwrap();
    let h = queue
        .schedule(Instant::from_picos(9), ComponentId(1), 'b')
        .unwrap();
    queue.clear();
    assert!(queue.is_empty());
    assert_eq!(queue.peek_time(), None);
    assert_eq!(queue.cancel(h), None);
    assert_eq!(queue.now(), Instant::from_picos(5));
    queue
        .schedule(Instant::from_picos(6), ComponentId(0), 'c')
        .unwrap();
    assert_eq!(queue.pop_next().unwrap().payload, 'c');
}

#[test]
fn run_until_runs_events_scheduled_by_handlers_and_skips_to_the_limit() {
    // A component that re-arms itself every 1 µs (one SERCOS cycle would be 1 ms; the rule
    // is the same): DESIGN.md, components say when they next need to run.
    let mut queue = EventQueue::new();
    queue
        .schedule(Instant::from_picos(0), ComponentId(0), 0u32)
        .unwrap();
    let period = Duration::from_micros(1);
    let mut seen = Vec::new();
    let ran = queue
        .run_until(Instant::from_picos(5_500_000), |queue, event| {
            seen.push((event.time.as_picos(), event.payload));
            queue.schedule(
                event.time.saturating_add(period),
                event.target,
                event.payload + 1,
            )?;
            Ok::<(), ScheduleError>(())
        })
        .unwrap();
    assert_eq!(ran, 6);
    assert_eq!(seen.last(), Some(&(5_000_000, 5)));
    assert_eq!(queue.now(), Instant::from_picos(5_500_000));
    assert_eq!(queue.peek_time(), Some(Instant::from_picos(6_000_000)));
}

#[test]
fn run_until_stops_at_the_first_handler_error() {
    let mut queue = EventQueue::new();
    for t in [10u64, 20, 30] {
        queue
            .schedule(Instant::from_picos(t), ComponentId(0), t)
            .unwrap();
    }
    let result = queue.run_until(Instant::from_picos(100), |_, event| {
        if event.payload == 20 {
            Err("stop")
        } else {
            Ok(())
        }
    });
    assert_eq!(result, Err("stop"));
    assert_eq!(queue.now(), Instant::from_picos(20));
    assert_eq!(queue.len(), 1);
}
