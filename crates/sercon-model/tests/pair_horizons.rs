//! The `ring_pair` bench's event loop (a horizon per chip, `benches/support/pair_loop.rs`)
//! gives exactly what a plain stepped run gives: the same output segments of each chip in the
//! same order,
//! the same received frames, RAM, registers and pin levels. The stepped run advances both
//! chips by half the fibre delay at a time, so every segment reaches its receiver before the
//! receiver's time passes its start (the line interface's contract, `Chip::line_input`).

#[path = "../benches/support/pair_loop.rs"]
mod pair_loop;
#[path = "../benches/support/pair_setup.rs"]
mod pair_setup;

use pair_loop::Pair;
use pair_setup::{Shape, any_shape, chips};
use proptest::prelude::*;
use sercon_model::Chip;
use sercon_model::pins::Pin;
use sercon_model::serial_port::{LineSegment, RxFrame};
use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

/// Runs `chips` to `until` in steps of half the fibre delay; the segments handed over.
fn stepped(chips: &mut [Chip; 2], delay: Duration, until: Instant) -> Vec<(usize, LineSegment)> {
    let mut log = Vec::new();
    pair_loop::stepped(
        chips,
        delay,
        until,
        |_, _| (),
        |i, _, seg| log.push((i, seg.clone())),
    );
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
    check(Shape::BENCH, 700);
    check(
        Shape {
            master_repeats: true,
            ..Shape::BENCH
        },
        400,
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(24)))]

    #[test]
    fn any_pair_runs_as_the_stepped_pair(shape in any_shape()) {
        check(shape, 300);
    }
}
