//! Ring simulation speed: simulated cycles of the `sercon bench` scenarios (master + 8
//! slaves at 250 µs; master + 8, 32, 128, 254 slaves at 4 ms), fast path.
//!
//! Two groups:
//! * `ring_cycle`: the ring running on, as `sercon bench` measures it: an iteration is one
//!   simulated cycle, and criterion's iterations of a sample are one `run_until` over as many
//!   cycles (`iter_custom`), so the time per iteration is the wall time per simulated cycle of
//!   a continuous run;
//! * `ring_step`: one `run_until` per cycle, as a caller stepping the ring cycle by cycle
//!   does. Each run's end bounds how far the slaves run ahead (`Simulation::run_ahead_limit`),
//!   so this costs more per cycle than the continuous run (docs/performance.md "Session 31").

#![allow(missing_docs)] // criterion_group! generates undocumented functions

use std::time::Instant as WallInstant;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use sercos_sim::scenario;
use sercos_wire::time::Duration;

fn cycles(c: &mut Criterion) {
    let mut group = c.benchmark_group("ring_cycle");
    group.sample_size(10);
    for s in scenario::all() {
        let Ok(mut sim) = scenario::prepare(&s) else {
            continue;
        };
        let cycle = Duration::from_micros(u64::from(s.ring.cycle_us));
        group.bench_function(BenchmarkId::from_parameter(&s.name), |b| {
            b.iter_custom(|iters| {
                let end = sim.now() + cycle.saturating_mul(iters);
                let wall = WallInstant::now();
                sim.run_until(end).ok();
                wall.elapsed()
            });
        });
    }
    group.finish();
}

fn steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("ring_step");
    group.sample_size(10);
    for s in scenario::all() {
        let Ok(mut sim) = scenario::prepare(&s) else {
            continue;
        };
        let cycle = Duration::from_micros(u64::from(s.ring.cycle_us));
        group.bench_function(BenchmarkId::from_parameter(&s.name), |b| {
            b.iter(|| {
                let t = sim.now() + cycle;
                sim.run_until(t).ok();
            });
        });
    }
    group.finish();
}

criterion_group!(benches, cycles, steps);
criterion_main!(benches);
