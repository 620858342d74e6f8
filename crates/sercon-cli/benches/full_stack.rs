//! Full-stack speed: the `sercon bench` full-stack scenarios under criterion — one phase-4
//! cycle of `stack-8` (master + 8 drives, 16 Mbit/s, 250 µs) and of `stack-n32` (32 drives,
//! 4 ms) with the host writing every drive's command, and the whole phase-up `phaseup-8`
//! (phase 0 to phase 4).

#![allow(missing_docs)] // criterion_group! generates undocumented functions

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use sercon_cli::full_stack::{self, RunningStack};
use sercos_wire::time::Duration;

fn cycles(c: &mut Criterion) {
    let mut group = c.benchmark_group("full_stack_cycle");
    group.sample_size(10);
    for s in [full_stack::stack_8(), full_stack::stack_n(32)] {
        let Ok(mut stack) = RunningStack::start(&s) else {
            eprintln!("{}: no phase 4, skipped", s.name);
            continue;
        };
        group.bench_function(BenchmarkId::from_parameter(&s.name), |b| {
            b.iter(|| stack.run_cycles(1).ok());
        });
    }
    group.finish();
}

fn phase_up(c: &mut Criterion) {
    let mut group = c.benchmark_group("full_stack_phaseup");
    group.sample_size(10);
    let s = full_stack::phaseup_8();
    let cycle = Duration::from_micros(u64::from(s.cycle_us));
    group.bench_function(BenchmarkId::from_parameter(&s.name), |b| {
        b.iter(|| {
            let mut ring = full_stack::build(&s).ok()?;
            full_stack::phase_up(&mut ring, cycle, Duration::from_secs(20)).ok()
        });
    });
    group.finish();
}

criterion_group!(benches, cycles, phase_up);
criterion_main!(benches);
