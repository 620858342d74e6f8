//! `Chip::next_output_bound`: no segment a chip releases starts before the earlier of that
//! bound and its queued output, asked right before the advance that released it (what a
//! ring simulation relies on when it lets a chip sleep through its receive events; 410B
//! §4.2.1 TRT: a transmit telegram starts TRT after the end of the MST, never earlier).

#[path = "../benches/support/pair_setup.rs"]
mod pair_setup;

use pair_setup::{Shape, chips};
use proptest::prelude::*;
use sercon_model::serial_port::{FrameHint, LineSegment, LineSignal, Shared};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::{Register, SerconBus, SerconBusExt};
use sercos_wire::line::{BitVec, Coding, Encoder, LineConfig, Polarity};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 03H bit 1 ENINT0: INT0 enabled.
const ENINT0: u16 = 1 << 1;

/// The earliest start of anything `c` may release from now on, by the queries.
fn promise(c: &Chip) -> Option<Instant> {
    match (c.next_output_bound(), c.next_line_output_at()) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// What a stepped run of two chips back to back saw.
#[derive(Debug, Default)]
struct Seen {
    /// Segments released (per chip).
    released: [usize; 2],
    /// Steps at which a chip's bound lay beyond its next internal event (a wake saved).
    skipped: [usize; 2],
}

/// Runs `pair` to `until` in steps of half the fibre delay (every segment reaches the
/// other chip before its time passes the start) and checks the promise at every step.
fn run(pair: &mut [Chip; 2], delay: Duration, until: Instant) -> Seen {
    let step = Duration::from_picos((delay.as_picos() / 2).max(1));
    let mut now = Instant::ZERO;
    let mut seen = Seen::default();
    let mut buf = Vec::new();
    while now < until {
        now = (now + step).min(until);
        for i in 0..2 {
            let c = &mut pair[i];
            let p = promise(c);
            if let (Some(b), Some(e)) = (c.next_output_bound(), c.next_internal_event_at())
                && b > e
            {
                seen.skipped[i] += 1;
            }
            c.advance_to(now);
            c.take_line_output(&mut buf);
            for seg in buf.drain(..) {
                assert!(
                    p.is_some_and(|p| seg.start >= p),
                    "chip {i}: a segment at {:?} before the promise {p:?}",
                    seg.start
                );
                seen.released[i] += 1;
                pair[1 - i].line_input(seg.delayed(delay));
            }
        }
    }
    seen
}

// 410B §4.2.1 TRT: the master's MDT and the slave's AT start at their TRT after the MST;
// the slave's receive events (MST, MDT) need no wake of their own.
#[test]
fn the_bench_pair_keeps_its_promises_and_saves_wakes() {
    let shape = Shape::BENCH;
    let mut pair = chips(shape);
    let seen = run(
        &mut pair,
        Duration::from_nanos(shape.delay_ns),
        Instant::ZERO + Duration::from_micros(600),
    );
    assert!(seen.released[0] > 20 && seen.released[1] > 20, "{seen:?}");
    assert!(
        seen.skipped[1] > 100,
        "the slave sleeps through its receive events: {seen:?}"
    );
    // The slave answered: the master received its AT (the bench's check).
    assert_eq!(pair[0].read_ram(29 + 7), 0x1000);
}

// 410B §4.1 03H ENINT0: with an interrupt output enabled every event may change INT0: the
// bound is the next internal event.
#[test]
fn an_enabled_interrupt_output_makes_every_event_count() {
    let shape = Shape::BENCH;
    let mut pair = chips(shape);
    for c in &mut pair {
        let c3 = c.read(Register::Ctrl3);
        c.write(Register::Ctrl3, c3 | ENINT0);
    }
    let seen = run(
        &mut pair,
        Duration::from_nanos(shape.delay_ns),
        Instant::ZERO + Duration::from_micros(300),
    );
    assert_eq!(seen.skipped, [0, 0], "{seen:?}");
    for c in &pair {
        assert_eq!(c.next_output_bound(), c.next_internal_event_at());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    // Any pair shape (cycle, telegram times, fibre delay, the master repeating too).
    #[test]
    fn any_pair_keeps_its_promises(
        tscyc in 90u16..200,
        mdt_trt in 1u16..30,
        at_trt in 30u16..80,
        delay_ns in 50u64..4000,
        master_repeats in any::<bool>(),
    ) {
        let shape = Shape { tscyc, mdt_trt, at_trt, delay_ns, master_repeats };
        let mut pair = chips(shape);
        let seen = run(
            &mut pair,
            Duration::from_nanos(delay_ns),
            Instant::ZERO + Duration::from_micros(300),
        );
        prop_assert!(seen.released[1] > 4, "{:?}", seen);
    }

    // Arbitrary RAM (headers, containers and service containers anywhere, overlapping) and
    // arbitrary frames: the bound never panics and no own telegram starts before it.
    #[test]
    fn arbitrary_ram_and_frames_keep_the_promise(
        ram in proptest::collection::vec(any::<u16>(), 64),
        fill in any::<u16>(),
        master in any::<bool>(),
        frames in proptest::collection::vec(
            (0u64..300, proptest::collection::vec(any::<u8>(), 0..40)),
            0..12,
        ),
    ) {
        let mut chip = Chip::new(ChipConfig::sercon816());
        chip.write(Register::MclkDiv, 31);
        for a in 0..2048u16 {
            chip.write_ram(a, fill.rotate_left(u32::from(a % 16)));
        }
        for (i, w) in ram.iter().enumerate() {
            chip.write_ram(i as u16, *w);
        }
        chip.write(Register::Tscyc0, 50);
        chip.write(Register::Phas, u16::from(fill as u8) | 0x0400);
        chip.write(Register::Jtrdel2, 3);
        chip.write(Register::Ctrl3, 1 << 8);
        chip.write(Register::Ctrl0C, if master { 0b11 | (1 << 10) } else { 1 });
        let mut frames = frames;
        frames.sort_by_key(|f| f.0);
        // 816 §2.3.1: 16 Mbit/s, 62.5 ns per bit.
        let bit_time = Duration::from_picos(62_500);
        let mut buf = Vec::new();
        let mut next = frames.into_iter().peekable();
        for t in 1..=400u64 {
            let now = Instant::ZERO + Duration::from_micros(t);
            // Frames are handed over a µs ahead of their start (as a ring delivers them).
            while let Some((start, bytes)) = next.next_if(|f| f.0 <= t) {
                let start = Instant::ZERO + Duration::from_micros(start + 1);
                let mut enc = Encoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnLow));
                let mut bits = BitVec::new();
                if enc.encode(&bytes, &mut bits).is_err() {
                    continue;
                }
                chip.line_input(LineSegment {
                    start,
                    bit_time,
                    signal: LineSignal::Bits(Shared::new(bits)),
                    level_before: false,
                    hint: Some(FrameHint { telegram: Shared::from(&bytes[..]), offset: 0 }),
                    distorted: false,
                });
            }
            let p = promise(&chip);
            chip.advance_to(now);
            chip.take_line_output(&mut buf);
            for seg in buf.drain(..) {
                prop_assert!(
                    p.is_some_and(|p| seg.start >= p),
                    "a segment at {:?} before the promise {:?}", seg.start, p
                );
            }
        }
    }
}
