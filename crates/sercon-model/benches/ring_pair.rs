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

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{EndMarker, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::{Duration, Instant};

use pair_loop::Pair;

/// 410B §4.1 0CH.0 MSTEN, 0CH.1 MSTMASTER, 0CH.10 CYCSTART; 3H.8 ENTMT; 1H.3 REPON.
const MSTEN: u16 = 1 << 0;
const MSTMASTER: u16 = 1 << 1;
const CYCSTART: u16 = 1 << 10;
const ENTMT: u16 = 1 << 8;
const REPON: u16 = 1 << 3;

/// A SERCON816 (16 Mbit/s by its straps, 816 §2.3.1) whose time unit is 0.5 µs and whose
/// cycle is 125 units.
fn chip() -> Chip {
    let mut c = Chip::new(ChipConfig::sercon816());
    // 410B §4.1 0EH MCLKDIV: 32 MHz / 16 = 2 MHz, a 0.5 µs unit.
    c.write(Register::MclkDiv, 15);
    c.write(Register::Tscyc0, 125);
    c
}

fn control(len: u16) -> u16 {
    ContainerControl::new(len, false, 0, false, true).map_or(0, |c| c.to_word())
}

/// Transmit at `at` (TRT `trt`, 8 words, single buffer, data at `at + 5`), then the end
/// marker or the next header at `at + 13`.
fn tx_block(c: &mut Chip, at: u16, adr: u8, trt: u16, pt: u16) {
    let h = TxHeader {
        adr,
        en: TxEnable::Continuous,
        trt,
        tlen: 8,
        pt,
        ..TxHeader::default()
    };
    c.write_ram_words(at, &h.to_words(Variant::Sercon816));
    c.write_ram(at + 4, control(8));
    let data: Vec<u16> = (0..8).map(|i| 0x1000 * u16::from(adr & 0xF) + i).collect();
    c.write_ram_words(at + 5, &data);
}

/// Receive header at `at` with one 8-word container (data at `at + 7`).
fn rx_block(c: &mut Chip, at: u16, adr: u8, trt: u16, pt: u16) {
    let h = RxHeader {
        adr,
        achk: true,
        trt,
        tlen: 8,
        pt,
        ..RxHeader::default()
    };
    c.write_ram_words(at, &h.to_words(Variant::Sercon816));
    c.write_ram_words(at + 5, &[control(8), 0]);
}

/// The master and the slave in phase 4, cycles running.
fn pair() -> Pair {
    let mut m = chip();
    let mut s = chip();
    // Master: COMPT0 → MDT (TRT 2 units after the MST) → AT → end marker.
    m.write_ram(0, 16);
    tx_block(&mut m, 16, 255, 2, 29);
    rx_block(&mut m, 29, 1, 40, 44);
    m.write_ram_words(44, &EndMarker::default().to_words());
    // Slave: COMPT0 → MDT → AT (TRT 40 units = 20 µs after the MST) → end marker.
    s.write_ram(0, 16);
    rx_block(&mut s, 16, 255, 2, 31);
    tx_block(&mut s, 31, 1, 40, 44);
    s.write_ram_words(44, &EndMarker::default().to_words());
    s.write(Register::Phas, 0xFF04);
    s.write(Register::Ctrl3, ENTMT);
    s.write(Register::Ctrl0C, MSTEN);
    // The master ends the ring: no repeater.
    let c1 = m.read(Register::Ctrl1);
    m.write(Register::Ctrl1, c1 & !REPON);
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    Pair::new([m, s], Duration::from_micros(1))
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
