//! Speed of the chip model's timing control: one SERCON816 running 1 s of simulated time with
//! 62.5 µs communication cycles, DIV_CLK at 4 pulses a cycle, CON_CLK on, and all four time
//! interrupts enabled to INT0. Target (task "modelaux"): ≥ 100× faster than real time, i.e.
//! ≤ 10 ms of wall time per simulated second.
//!
//! Programming (816 at MCLK = 32 MHz, documented in docs/performance.md):
//! * 0EH MCLKDIV = 15: the timing registers count 0.5 µs (410B §4.1 0EH: "fMCLK/1 MHz - 1" for
//!   1 µs; half of it for 0.5 µs), so TSCYC0 = 125 gives exactly 62.5 µs, which 1 µs steps
//!   cannot (62.5 µs is the shortest SERCOS II cycle, 16 Mbit/s rings).
//! * TINT0–3 = 10, 40, 70, 100 (5, 20, 35, 50 µs); CON_CLK on from TINT0 to TINT1 (0CH.5).
//! * TDIVCLK = 5, DTDIVCLK = 30, NDIVCLK = 4: DIV_CLK pulses at 2.5, 17.5, 32.5, 47.5 µs.
//! * 7H EN0_INT = INT_TIME0-3 (5H.9-12), 3H ENINT0 = 1.
//! * Timing control runs as a master started once by CYCSTART (0CH.10) and then continues
//!   cycle after cycle (NCYC = 0).
//!
//! Run: `CARGO_TARGET_DIR=/work/targets/modelaux cargo bench -p sercon-model --bench timing`

// criterion_group! generates an undocumented pub fn.
#![allow(missing_docs)]

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use sercon_model::Chip;
use sercon_model::config::ChipConfig;
use sercon_model::pins::{Pin, PinSet};
use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

/// The 62.5 µs cycle programmed below.
const CYCLE: Duration = Duration::from_picos(62_500_000);
const ONE_SECOND: Duration = Duration::from_secs(1);

/// 410B §4.1 0CH.0 MSTEN: with it the master also sends an MST at every cycle start (through
/// the serial port); without it the chip runs its timing control only (CYCSTART, TINT0–3,
/// CON_CLK, DIV_CLK), which is what the target is about.
fn programmed_chip(traced: PinSet, msten: bool) -> Chip {
    let mut chip = Chip::new(ChipConfig::sercon816());
    chip.set_traced_pins(traced);
    let w = |chip: &mut Chip, a: u8, v: u16| chip.write_register(a, v);
    w(&mut chip, 0x0E, 15); // MCLKDIV = 15: 0.5 µs ticks at 32 MHz
    w(&mut chip, 0x0F, 125); // TSCYC0: 62.5 µs
    w(&mut chip, 0x10, 125); // TSCYC1
    w(&mut chip, 0x13, 0); // TCNTST
    w(&mut chip, 0x14, 0); // TCYCSTART
    w(&mut chip, 0x1A, 10); // TINT0
    w(&mut chip, 0x1B, 40); // TINT1
    w(&mut chip, 0x1C, 70); // TINT2
    w(&mut chip, 0x1D, 100); // TINT3
    w(&mut chip, 0x1E, 5); // TDIVCLK
    w(&mut chip, 0x1F, 30); // DTDIVCLK
    w(&mut chip, 0x20, 4); // NDIVCLK = 4, 1-active, DIVCLKMODE = 0
    w(&mut chip, 0x07, 0x1E00); // EN0_INT: INT_TIME0-3
    w(&mut chip, 0x03, 0x0002); // ENINT0
    // 0CH: [MSTEN |] MSTMASTER | ENCONCLK | CYCSTART, NCYC = 0.
    let msten = if msten { 0x0001 } else { 0 };
    w(&mut chip, 0x0C, msten | 0x0002 | 0x0020 | 0x0400);
    chip
}

fn run_free(traced: PinSet) -> usize {
    run_free_with(traced, false)
}

/// Free running with MSTEN: the line output (an MST and filler a cycle) is taken every
/// millisecond, as a simulator would.
fn run_free_sending(traced: PinSet) -> usize {
    run_free_with(traced, true)
}

fn run_free_with(traced: PinSet, msten: bool) -> usize {
    let mut chip = programmed_chip(traced, msten);
    let mut line = Vec::new();
    let mut events = Vec::new();
    let mut n = 0;
    let end = Instant::ZERO + ONE_SECOND;
    // Drain every simulated millisecond, as a trace writer would.
    let mut t = Instant::ZERO;
    while t < end {
        t += Duration::from_millis(1);
        chip.advance_to(t);
        events.clear();
        chip.drain_pin_events(&mut events);
        n += events.len();
        line.clear();
        chip.take_line_output(&mut line);
    }
    n
}

/// A host that services INT0 every cycle: reads 5H and clears the flags it saw.
fn run_with_host(traced: PinSet) -> usize {
    let mut chip = programmed_chip(traced, false);
    let mut events = Vec::new();
    let mut n = 0;
    let mut t = Instant::ZERO;
    let end = Instant::ZERO + ONE_SECOND;
    while t < end {
        t += CYCLE;
        chip.advance_to(t);
        let flags = chip.read_register(0x05);
        chip.write_register(0x05, flags); // 410B 4H/5H (ERRATA): write 1 clears
        events.clear();
        chip.drain_pin_events(&mut events);
        n += events.len();
    }
    n
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("timing_816_62us5_1s");
    g.sample_size(20);
    let traced = PinSet::of(&[Pin::ConClk, Pin::DivClk, Pin::Int0]);
    // The programming really runs 16 000 cycles: CON_CLK 2 edges and DIV_CLK 8 edges a cycle,
    // INT0 rising once (free running, never cleared) or once a cycle plus its clear (host).
    let free = run_free(traced);
    let host = run_with_host(traced);
    let sending = run_free_sending(traced);
    assert_eq!(free, 16_000 * 10 + 1, "free-running events in 1 s");
    assert_eq!(sending, free, "the MSTs change no traced pin");
    assert_eq!(host, 16_000 * 12, "events with a host clearing INT0 in 1 s");
    eprintln!("events in 1 s: free running {free}, host clearing INT0 {host}");
    for (name, pins) in [("untraced", PinSet::EMPTY), ("traced", traced)] {
        g.bench_function(format!("free_running/{name}"), |b| {
            b.iter_batched(|| pins, run_free, BatchSize::SmallInput)
        });
        g.bench_function(format!("host_acks_int0/{name}"), |b| {
            b.iter_batched(|| pins, run_with_host, BatchSize::SmallInput)
        });
        g.bench_function(format!("master_sending_msts/{name}"), |b| {
            b.iter_batched(|| pins, run_free_sending, BatchSize::SmallInput)
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
