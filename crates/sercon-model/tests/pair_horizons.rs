//! The `ring_pair` bench's event loop (a horizon per chip, `benches/support/pair_loop.rs`)
//! gives exactly what a plain stepped run gives: the same output segments of each chip in the
//! same order,
//! the same received frames, RAM, registers and pin levels. The stepped run advances both
//! chips by half the fibre delay at a time, so every segment reaches its receiver before the
//! receiver's time passes its start (the line interface's contract, `Chip::line_input`).

#[path = "../benches/support/pair_loop.rs"]
mod pair_loop;

use pair_loop::Pair;
use proptest::prelude::*;
use sercon_model::pins::Pin;
use sercon_model::serial_port::{LineSegment, RxFrame};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{EndMarker, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 0CH.0 MSTEN, 0CH.1 MSTMASTER, 0CH.10 CYCSTART; 3H.8 ENTMT; 1H.3 REPON.
const MSTEN: u16 = 1 << 0;
const MSTMASTER: u16 = 1 << 1;
const CYCSTART: u16 = 1 << 10;
const ENTMT: u16 = 1 << 8;
const REPON: u16 = 1 << 3;

/// The shape of one pair: cycle, telegram times (in 0.5 µs units after the MST, 410B §4.2.1
/// TRT), fibre delay, and whether the master's repeater is on too (then each chip's output
/// depends on the other's at once, which the loop's "reply" bound covers).
#[derive(Debug, Clone, Copy)]
struct Shape {
    tscyc: u16,
    mdt_trt: u16,
    at_trt: u16,
    delay_ns: u64,
    master_repeats: bool,
}

/// A SERCON816 at 16 Mbit/s (816 §2.3.1) with a 0.5 µs unit (410B §4.1 0EH MCLKDIV = 15).
fn chip(tscyc: u16) -> Chip {
    let mut c = Chip::new(ChipConfig::sercon816());
    c.write(Register::MclkDiv, 15);
    c.write(Register::Tscyc0, tscyc);
    c
}

fn control(len: u16) -> u16 {
    ContainerControl::new(len, false, 0, false, true).map_or(0, |c| c.to_word())
}

/// 410B §4.2.1 transmit header at `at`, one 8-word container (§4.2.2), data at `at + 5`.
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

/// 410B §4.2.1 receive header at `at` with one 8-word container.
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

/// The bench's master and slave in phase 4, in the given shape.
fn chips(shape: Shape) -> [Chip; 2] {
    let mut m = chip(shape.tscyc);
    let mut s = chip(shape.tscyc);
    m.write_ram(0, 16);
    tx_block(&mut m, 16, 255, shape.mdt_trt, 29);
    rx_block(&mut m, 29, 1, shape.at_trt, 44);
    m.write_ram_words(44, &EndMarker::default().to_words());
    s.write_ram(0, 16);
    rx_block(&mut s, 16, 255, shape.mdt_trt, 31);
    tx_block(&mut s, 31, 1, shape.at_trt, 44);
    s.write_ram_words(44, &EndMarker::default().to_words());
    s.write(Register::Phas, 0xFF04);
    s.write(Register::Ctrl3, ENTMT);
    s.write(Register::Ctrl0C, MSTEN);
    if !shape.master_repeats {
        let c1 = m.read(Register::Ctrl1);
        m.write(Register::Ctrl1, c1 & !REPON);
    }
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    [m, s]
}

/// Runs `chips` to `until` in steps of half the fibre delay; the segments handed over.
fn stepped(chips: &mut [Chip; 2], delay: Duration, until: Instant) -> Vec<(usize, LineSegment)> {
    let step = Duration::from_picos((delay.as_picos() / 2).max(1));
    let mut now = Instant::ZERO;
    let mut log = Vec::new();
    let mut buf = Vec::new();
    while now < until {
        now = (now + step).min(until);
        for i in 0..2 {
            chips[i].advance_to(now);
            chips[i].take_line_output(&mut buf);
            for seg in buf.drain(..) {
                log.push((i, seg.clone()));
                chips[1 - i].line_input(seg.delayed(delay));
            }
        }
    }
    log
}

/// What a chip shows: received frames, RAM, registers 00H–3FH, driven pin levels.
fn state(c: &mut Chip) -> (Vec<RxFrame>, Vec<u16>, Vec<u16>, Vec<bool>) {
    let mut frames = Vec::new();
    c.take_rx_frames(&mut frames);
    let ram = (0..2048).map(|a| c.read_ram(a)).collect();
    let regs = (0..0x40u8).map(|a| c.read_register(a)).collect();
    let pins = [Pin::Int0, Pin::Int1, Pin::ConClk, Pin::DivClk, Pin::Wdogn]
        .into_iter()
        .map(|p| c.pin_level(p))
        .collect();
    (frames, ram, regs, pins)
}

/// Runs `shape` both ways for `us` µs and compares everything.
fn check(shape: Shape, us: u64) {
    let delay = Duration::from_picos(shape.delay_ns * 1000);
    let until = Instant::ZERO + Duration::from_micros(us);
    let mut plain = chips(shape);
    let want = stepped(&mut plain, delay, until);
    let mut pair = Pair::new(chips(shape), delay);
    pair.log = Some(Vec::new());
    pair.run_to(until);
    let got = pair.log.take().unwrap_or_default();
    assert!(
        want.iter().filter(|(i, _)| *i == 1).count() > 4,
        "{shape:?}: the slave answered"
    );
    // Per chip: the two loops interleave the chips' hand-overs differently.
    for i in 0..2 {
        let of = |log: &[(usize, LineSegment)]| -> Vec<LineSegment> {
            log.iter()
                .filter(|(j, _)| *j == i)
                .map(|(_, s)| s.clone())
                .collect()
        };
        assert_eq!(
            of(&got),
            of(&want),
            "{shape:?}: output segments of chip {i}"
        );
    }
    for (i, c) in plain.iter_mut().enumerate() {
        let chip = pair.chips.get_mut(i).expect("two chips");
        assert_eq!(chip.now(), c.now());
        assert_eq!(state(chip), state(c), "{shape:?}: chip {i}");
    }
}

#[test]
fn the_bench_pair_runs_as_the_stepped_pair() {
    // The bench: 62.5 µs cycle, MDT at TRT 2, AT at TRT 40, 1 µs of fibre.
    let bench = Shape {
        tscyc: 125,
        mdt_trt: 2,
        at_trt: 40,
        delay_ns: 1000,
        master_repeats: false,
    };
    check(bench, 700);
    check(
        Shape {
            master_repeats: true,
            ..bench
        },
        400,
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn any_pair_runs_as_the_stepped_pair(
        tscyc in 90u16..200,
        mdt_trt in 1u16..30,
        at_trt in 30u16..80,
        delay_ns in 50u64..4000,
        master_repeats in any::<bool>(),
    ) {
        check(Shape { tscyc, mdt_trt, at_trt, delay_ns, master_repeats }, 300);
    }
}
