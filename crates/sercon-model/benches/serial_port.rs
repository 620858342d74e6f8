//! Line interface speed: a slave receiving a 100-byte MDT from its hint vs. decoding its bits,
//! and a repeater forwarding it (spec-notes "Serial port": hints, forwarding without per-bit
//! work).

// criterion_group! generates an undocumented pub fn.
#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use sercon_model::serial_port::LineSegment;
use sercon_model::{Chip, ChipConfig};
use sercon_regs::{Register, SerconBusExt};
use sercos_wire::time::{Duration, Instant};
use std::hint::black_box;

/// A SERCON816 with normal straps (TM0 = TM1 = 1, no test signal) and the repeater
/// (410B §4.1 1H.3 REPON) as asked.
fn chip(repon: bool) -> Chip {
    let mut chip = Chip::new(ChipConfig::sercon816());
    let c1 = chip.read(Register::Ctrl1);
    chip.write(Register::Ctrl1, (c1 & !(1 << 3)) | (u16::from(repon) << 3));
    chip
}

fn telegram_segments() -> Vec<LineSegment> {
    let mut master = chip(false);
    let mdt: Vec<u8> = (0..100u8).collect();
    let at = Instant::ZERO + Duration::from_micros(2);
    let end = master.transmit_telegram(at, &mdt).unwrap_or(at);
    master.advance_to(end);
    let mut out = Vec::new();
    master.take_line_output(&mut out);
    out
}

fn bench(c: &mut Criterion) {
    let segs = telegram_segments();
    let stripped: Vec<_> = segs
        .iter()
        .cloned()
        .map(|mut s| {
            s.hint = None;
            s
        })
        .collect();
    c.bench_function("receive 100-byte MDT from hint", |b| {
        b.iter(|| {
            let mut slave = chip(false);
            for s in &segs {
                slave.line_input(black_box(s.clone()));
            }
            slave
        })
    });
    c.bench_function("receive 100-byte MDT by decoding", |b| {
        b.iter(|| {
            let mut slave = chip(false);
            for s in &stripped {
                slave.line_input(black_box(s.clone()));
            }
            slave
        })
    });
    c.bench_function("repeat 100-byte MDT", |b| {
        b.iter(|| {
            let mut slave = chip(true);
            let mut out = Vec::new();
            for s in &segs {
                slave.line_input(black_box(s.clone()));
            }
            slave.advance_to(Instant::ZERO + Duration::from_micros(60));
            slave.take_line_output(&mut out);
            out
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
