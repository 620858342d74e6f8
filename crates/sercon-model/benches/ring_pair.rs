//! Controller pair speed (task tp2, target ≥ 50× real time): a SERCON816 master and one
//! slave back to back (1 µs of fibre each way) at 16 Mbit/s, 62.5 µs cycle (MCLKDIV = 15:
//! 0.5 µs time unit, TSCYC0 = 125), phase 4, an 8-word MDT and an 8-word AT per cycle
//! (410B §4.2.1–§4.2.3; 816 §2.3.1). The figure is the wall time per simulated millisecond;
//! `docs/performance.md`, "Controller pair (sercon-model)".

// criterion_group! generates an undocumented pub fn.
#![allow(missing_docs)]

// The event loop, shared with the test that checks it against a stepped run
// (tests/pair_horizons.rs).
#[path = "support/pair_loop.rs"]
mod pair_loop;
// The two chips, shared with the same test.
#[path = "support/pair_setup.rs"]
mod pair_setup;

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group};
use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

use pair_loop::Pair;
use pair_setup::{Shape, chips};

/// The master and the slave in phase 4, cycles running.
fn pair() -> Pair {
    let shape = Shape::BENCH;
    Pair::new(chips(shape), Duration::from_nanos(shape.delay_ns))
}

fn bench(c: &mut Criterion) {
    let mut warm = pair();
    // Phase 4 running: a few cycles in.
    warm.run_to(Instant::ZERO + Duration::from_micros(500));
    let check = warm.chips[0].read_ram(29 + 7);
    assert_eq!(check, 0x1000, "the master received the slave's AT");
    let mut g = c.benchmark_group("ring_pair");
    // One simulated millisecond: 16 cycles of 62.5 µs.
    g.throughput(Throughput::Elements(16));
    // Steady state: one pair runs on, each iteration simulates the next millisecond (what a
    // long simulation does; after criterion's warm-up the receive logs are full and every
    // buffer has its working size). The target (≤ 20 µs) is measured here.
    let mut running = warm.clone();
    g.bench_function(
        "master+slave 16 Mbit/s 62.5 µs phase 4, 1 ms simulated, steady",
        |b| {
            b.iter(|| {
                let until = running.now + Duration::from_millis(1);
                running.run_to(until);
                black_box(running.now)
            })
        },
    );
    // Each iteration from a copy of the state 0.5 ms in (the figures before modelperf3): the
    // copy's buffers have no spare capacity and its receive log is nearly empty, so every
    // iteration also pays the first growth of each buffer.
    g.bench_function(
        "master+slave 16 Mbit/s 62.5 µs phase 4, 1 ms simulated",
        |b| {
            b.iter_batched(
                || warm.clone(),
                |mut p| {
                    let until = p.now + Duration::from_millis(1);
                    p.run_to(until);
                    black_box(p)
                },
                criterion::BatchSize::LargeInput,
            )
        },
    );
    g.finish();
}

criterion_group!(benches, bench);

/// `RING_PAIR_PROFILE=<ms>` runs that many simulated milliseconds from the warmed-up state
/// and exits, without criterion (for `valgrind --tool=callgrind`: a fixed amount of work);
/// `RING_PAIR_REPEAT=<n>` does that `n` times, each from a copy of the warmed-up state (for
/// comparing CPU times of two builds with `/usr/bin/time` on a busy machine).
fn main() {
    let var = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<u64>().ok());
    if let Some(ms) = var("RING_PAIR_PROFILE") {
        let mut warm = pair();
        warm.run_to(Instant::ZERO + Duration::from_micros(500));
        for _ in 0..var("RING_PAIR_REPEAT").unwrap_or(1) {
            let mut p = warm.clone();
            let until = p.now + Duration::from_millis(ms);
            p.run_to(until);
            black_box(p);
        }
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
