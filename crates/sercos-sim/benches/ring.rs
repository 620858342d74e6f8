//! Ring simulation speed: simulated cycles of the `sercon bench` scenarios (master + 8
//! slaves at 250 µs; master + 8, 32, 128, 254 slaves at 4 ms), fast path.

#![allow(missing_docs)] // criterion_group! generates undocumented functions

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
            b.iter(|| {
                let t = sim.now() + cycle;
                sim.run_until(t).ok();
            });
        });
    }
    group.finish();
}

criterion_group!(benches, cycles);
criterion_main!(benches);
