//! Event queue throughput: the "hold" model (pop the next event, schedule one a little later)
//! with as many pending events as a full ring has stations, and with cancellations.
//!
//! Run: `cargo bench -p sercos-sim --bench event_queue`
// Benchmarks may unwrap: a failure aborts the measurement.
#![allow(clippy::unwrap_used)]
#![allow(missing_docs)] // criterion_group! generates undocumented functions

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use sercos_sim::event_queue::{ComponentId, EventQueue};
use sercos_wire::time::{Duration, Instant};

/// A small deterministic generator (64-bit LCG, Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }
}

/// A queue with `pending` events spread over one 1 ms cycle.
fn filled(pending: u32, rng: &mut Lcg) -> EventQueue<u64> {
    let mut queue = EventQueue::with_capacity(pending as usize * 2);
    for component in 0..pending {
        let at = Instant::from_picos(rng.next() % 1_000_000_000);
        queue.schedule(at, ComponentId(component), 0).unwrap();
    }
    queue
}

const STEPS: u64 = 10_000;

fn hold(c: &mut Criterion) {
    let mut group = c.benchmark_group("event_queue");
    group.throughput(Throughput::Elements(STEPS));
    for pending in [16u32, 256, 4096] {
        group.bench_function(format!("hold_{pending}_pending"), |b| {
            let mut rng = Lcg(1);
            let mut queue = filled(pending, &mut rng);
            b.iter(|| {
                for _ in 0..STEPS {
                    let event = queue.pop_next().unwrap();
                    let delay = Duration::from_picos(rng.next() % 1_000_000_000);
                    queue
                        .schedule(
                            event.time.saturating_add(delay),
                            event.target,
                            event.payload + 1,
                        )
                        .unwrap();
                }
                black_box(queue.peek_time())
            });
        });
    }
    group.bench_function("hold_256_pending_cancel_half", |b| {
        let mut rng = Lcg(2);
        let mut queue = filled(256, &mut rng);
        b.iter(|| {
            for _ in 0..STEPS {
                let event = queue.pop_next().unwrap();
                let now = event.time;
                // A timeout that is usually cancelled, as a watchdog re-armed every cycle.
                let timeout = queue
                    .schedule(
                        now.saturating_add(Duration::from_picos(2_000_000_000)),
                        ComponentId(u32::MAX),
                        0,
                    )
                    .unwrap();
                let delay = Duration::from_picos(rng.next() % 1_000_000_000);
                queue
                    .schedule(now.saturating_add(delay), event.target, event.payload)
                    .unwrap();
                black_box(queue.cancel(timeout));
            }
            black_box(queue.len())
        });
    });
    group.finish();
}

criterion_group!(benches, hold);
criterion_main!(benches);
