//! `Chip::next_output_bound`: no segment a chip releases starts before the earlier of that
//! bound and its queued output, asked right before the advance that released it (what a
//! ring simulation relies on when it lets a chip sleep through its receive events; 410B
//! §4.2.1 TRT: a transmit telegram starts TRT after the end of the MST, never earlier).

// The stepped reference run (its event loop is not used here).
#[path = "../benches/support/pair_loop.rs"]
#[allow(dead_code)]
mod pair_loop;
#[path = "../benches/support/pair_setup.rs"]
mod pair_setup;

mod common;

use pair_setup::{Shape, any_shape, chips};
use proptest::prelude::*;
use sercon_model::serial_port::{LineSegment, LineSignal};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{EndMarker, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
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
    let mut skipped = [0; 2];
    let mut released = [0; 2];
    pair_loop::stepped(
        pair,
        delay,
        until,
        |i, c| {
            if let (Some(b), Some(e)) = (c.next_output_bound(), c.next_internal_event_at())
                && b > e
            {
                skipped[i] += 1;
            }
            promise(c)
        },
        |i, p, seg| {
            assert!(
                p.is_some_and(|p| seg.start >= p),
                "chip {i}: a segment at {:?} before the promise {p:?}",
                seg.start
            );
            released[i] += 1;
        },
    );
    Seen { released, skipped }
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

/// Steps the bench pair at half the fibre's delay for 600 µs: `visit` advances chip `i` to
/// `now` (and checks what it will), then its output reaches the other chip.
fn step_bench_pair(mut visit: impl FnMut(&mut Chip, usize, Instant)) -> [Chip; 2] {
    let shape = Shape::BENCH;
    let mut pair = chips(shape);
    let delay = Duration::from_nanos(shape.delay_ns);
    let step = Duration::from_picos((delay.as_picos() / 2).max(1));
    let until = Instant::ZERO + Duration::from_micros(600);
    let mut now = Instant::ZERO;
    let mut buf = Vec::new();
    while now < until {
        now = (now + step).min(until);
        for i in 0..2 {
            let c = &mut pair[i];
            visit(c, i, now);
            c.take_line_output(&mut buf);
            for seg in buf.drain(..) {
                pair[1 - i].line_input(seg.delayed(delay));
            }
        }
    }
    pair
}

// 410B §4.2.1 TRT: an advance that stops before the chip's next possible own telegram
// (`Chip::advance_before_output`, a simulation running a chip ahead between its inputs)
// keeps the bound it had; that bound is the one the chip walks for afresh after a plain
// advance to the same instant, and the chip is left as that advance leaves it.
#[test]
fn an_advance_before_the_output_keeps_the_walked_bound() {
    let mut kept = 0;
    let mut pair = step_bench_pair(|c, _, now| {
        if c.next_output_bound().is_some_and(|b| b > now) {
            let mut plain = c.clone();
            plain.advance_to(now);
            c.advance_before_output(now);
            assert_eq!(
                c.next_output_bound(),
                plain.next_output_bound(),
                "at {now:?}"
            );
            assert_eq!(c.next_internal_event_at(), plain.next_internal_event_at());
            assert_eq!(c.read_register(3), plain.read_register(3));
            kept += 1;
        } else {
            c.advance_to(now);
        }
    });
    assert!(kept > 100, "{kept} advances before the output");
    // The slave answered: the master received its AT (the bench's check).
    assert_eq!(pair[0].read_ram(29 + 7), 0x1000);
}

// 410B §4.2.1 TRT, §4.1 0CH: the bound remembered by `Chip::next_output_for_any_input` (a
// master's, asked once per pass of its telegram) and by `Chip::next_output_bound` outlives
// the line input that follows only where that input cannot move it: a master's MST coming
// back round the ring leaves it (a master's block starts with its cycle start), a slave's
// MST does not (its block starts with it). Each chip asks both after its advance; the other
// chip's output then reaches it, and the bound it gives before its next advance is the one
// found afresh (a host write of a word's own value drops what the chip remembered).
#[test]
fn a_bound_remembered_before_a_line_input_is_the_one_found_after_it() {
    let mut promised = [0; 2];
    let mut pair = step_bench_pair(|c, i, now| {
        let last = c.config().variant.ram_words() - 1;
        let mut fresh = c.clone();
        let word = fresh.read_ram(last);
        fresh.write_ram(last, word);
        assert_eq!(
            c.next_output_bound(),
            fresh.next_output_bound(),
            "chip {i} at {now:?}"
        );
        c.advance_to(now);
        if c.next_output_for_any_input().is_some() {
            promised[i] += 1;
        }
        let _ = c.next_output_bound();
    });
    assert!(promised[0] > 100 && promised[1] == 0, "{promised:?}");
    // The slave answered: the master received its AT (the bench's check).
    assert_eq!(pair[0].read_ram(29 + 7), 0x1000);
}

// 410B §4.2.1 TRT "after end of MST", §4.1 0AH PHAS0 / 0CH COMBLK0: a slave that has an
// MST to process is bound by the first transmit header of the block that MST starts, not by
// the MST's end: no bound lies at the end of an MST (the bound before it did), and some are
// the start of the AT it sends next.
#[test]
fn a_slave_is_bound_by_the_at_of_the_block_its_mst_starts() {
    let shape = Shape::BENCH;
    let delay = Duration::from_nanos(shape.delay_ns);
    let mut pair = chips(shape);
    let mut bounds = Vec::new();
    let mut ats = Vec::new();
    let mut mst_ends = Vec::new();
    pair_loop::stepped(
        &mut pair,
        delay,
        Instant::ZERO + Duration::from_micros(600),
        |i, c| {
            if i == 1
                && let (Some(b), Some(e)) = (c.next_output_bound(), c.next_internal_event_at())
                && b > e
            {
                bounds.push(b);
            }
            promise(c)
        },
        |i, _, seg| {
            let adr = seg
                .hint
                .as_ref()
                .map(|h| (h.telegram.first().copied(), h.telegram.len()));
            match (i, adr) {
                // The master's MSTs (ADR 255, one data byte; sercos-telegrams.md), where
                // they end at the slave.
                (0, Some((Some(255), 2))) => {
                    mst_ends.extend(seg.end().map(|e| e + delay));
                }
                // The slave's own telegrams (it repeats MST and MDT, ADR 255).
                (1, Some((Some(a), _))) if a != 255 => ats.push(seg.start),
                _ => {}
            }
        },
    );
    assert!(ats.len() > 5 && mst_ends.len() > 5, "{ats:?} {mst_ends:?}");
    // In the steady cycles (after the first AT; before it the slave starts up).
    let first = ats.first().copied().unwrap_or(Instant::ZERO);
    let steady: Vec<Instant> = bounds.into_iter().filter(|b| *b > first).collect();
    let near = |b: Instant, t: Instant| b >= t && b < t + Duration::from_nanos(200);
    for b in &steady {
        assert!(
            !mst_ends.iter().any(|m| near(*b, *m)),
            "a bound at {b:?} is the end of an MST ({mst_ends:?})"
        );
    }
    let at_bounds = steady.iter().filter(|b| ats.contains(b)).count();
    assert!(
        at_bounds > 5,
        "{at_bounds} of {} bounds are AT starts",
        steady.len()
    );
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

/// A one-container control word of `len` words (410B §4.2.2 LEN, LASTDC = 1).
fn control(len: u16) -> u16 {
    ContainerControl::new(len, false, 0, false, true).map_or(0, |c| c.to_word())
}

/// A master whose list is COMPT0 → MDT (TRT 2) → AT 1 (TRT 20, its data container laid over
/// the header at 37) → AT 2 (TRT 60) → the header at 37 (a transmit header, TRT 120, EN = 0)
/// → end marker; and that header.
fn master_with_a_header_ahead() -> (Chip, TxHeader) {
    let v = Variant::Sercon816;
    let mut m = Chip::new(ChipConfig::sercon816());
    m.write(Register::MclkDiv, 15);
    m.write(Register::Tscyc0, 250);
    let c1 = m.read(Register::Ctrl1);
    m.write(Register::Ctrl1, c1 & !(1 << 3));
    let mdt = TxHeader {
        adr: 255,
        en: TxEnable::Continuous,
        trt: 2,
        tlen: 1,
        pt: 30,
        ..TxHeader::default()
    };
    m.write_ram(0, 16);
    m.write_ram_words(16, &mdt.to_words(v));
    m.write_ram_words(20, &[control(1), 0x1234]);
    let at1 = RxHeader {
        adr: 1,
        achk: true,
        trt: 20,
        tlen: 4,
        pt: 50,
        ..RxHeader::default()
    };
    m.write_ram_words(30, &at1.to_words(v));
    m.write_ram_words(35, &[control(4), 0]);
    let at2 = RxHeader {
        adr: 2,
        achk: true,
        trt: 60,
        tlen: 1,
        pt: 37,
        ..RxHeader::default()
    };
    m.write_ram_words(50, &at2.to_words(v));
    m.write_ram_words(55, &[control(1), 0, 0]);
    let third = TxHeader {
        adr: 3,
        en: TxEnable::Off,
        trt: 120,
        tlen: 1,
        pt: 70,
        ..TxHeader::default()
    };
    m.write_ram_words(37, &third.to_words(v));
    m.write_ram_words(41, &[control(1), 0x5678]);
    m.write_ram_words(70, &EndMarker::default().to_words());
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, 1 << 8);
    m.write(Register::Ctrl0C, 0b11 | (1 << 10));
    (m, third)
}

/// The header at 37 of [`master_with_a_header_ahead`] with EN = 2, and AT 1's telegram
/// (ADR 1) carrying it over that header (words little-endian, 410B §4.2.2 POS).
fn at1_enabling(third: TxHeader) -> (TxHeader, Vec<u8>) {
    let enabled = TxHeader {
        en: TxEnable::Continuous,
        ..third
    };
    let mut at1_bytes = vec![1u8];
    for w in enabled.to_words(Variant::Sercon816) {
        at1_bytes.extend_from_slice(&w.to_le_bytes());
    }
    (enabled, at1_bytes)
}

/// The master of [`master_with_a_header_ahead`] given its two ATs a µs before they start
/// (15 and 35 µs after its MST), AT 1 carrying the header at 37 with EN = 2 (words
/// little-endian, 410B §4.2.2 POS), advanced µs by µs to 120 µs, every segment checked
/// against the promise asked before its advance. With `keep`, every advance that stops
/// before the bound is `Chip::advance_before_output`, checked against a plain advance of a
/// copy. Returns the master, the starts of its own telegrams, the advances kept and the
/// header's first word as AT 1 carries it.
fn header_ahead_run(keep: bool) -> (Chip, Vec<Instant>, usize, u16) {
    let v = Variant::Sercon816;
    let (mut m, third) = master_with_a_header_ahead();
    let (enabled, at1_bytes) = at1_enabling(third);
    let mut buf = Vec::new();
    let mut own = Vec::new();
    let mut mst_at = None;
    let mut fed = 0;
    let mut kept = 0;
    for t in 1..=120u64 {
        let now = Instant::ZERO + Duration::from_micros(t);
        if let Some(t0) = mst_at {
            if fed == 0 && now + Duration::from_micros(1) >= t0 + Duration::from_micros(15) {
                m.line_input(common::hinted_frame(
                    t0 + Duration::from_micros(15),
                    &at1_bytes,
                ));
                fed = 1;
            }
            if fed == 1 && now + Duration::from_micros(1) >= t0 + Duration::from_micros(35) {
                m.line_input(common::hinted_frame(
                    t0 + Duration::from_micros(35),
                    &[2, 0xAA, 0x55],
                ));
                fed = 2;
            }
        }
        let p = promise(&m);
        if keep && m.next_output_bound().is_some_and(|b| b > now) {
            let mut plain = m.clone();
            plain.advance_to(now);
            m.advance_before_output(now);
            assert_eq!(
                m.next_output_bound(),
                plain.next_output_bound(),
                "at {now:?}"
            );
            kept += 1;
        } else {
            m.advance_to(now);
        }
        m.take_line_output(&mut buf);
        for seg in buf.drain(..) {
            assert!(
                p.is_some_and(|p| seg.start >= p),
                "a segment at {:?} before the promise {p:?}",
                seg.start
            );
            if let LineSignal::Bits(_) = seg.signal {
                mst_at.get_or_insert(seg.start);
                own.push(seg.start);
            }
        }
    }
    assert_eq!(fed, 2);
    let word0 = enabled.to_words(v)[0];
    (m, own, kept, word0)
}

// 410B §4.2.1/§4.2.2: a receive container laid over a transmit header two headers ahead (a
// programming error the chip still runs): the first AT's data turn that header's EN from 0
// to 2, so the master sends a third telegram after the second AT. What the bound walked
// before the data arrived must not survive the controller's own write.
#[test]
fn received_data_that_enable_a_header_ahead_move_the_bound() {
    let (mut m, own, _, word0) = header_ahead_run(false);
    // MST, MDT, and the third telegram 60 µs after the MST's end.
    assert!(own.len() >= 3, "{own:?}");
    assert_eq!(m.read_ram(37), word0, "AT 1 stored over it");
}

// 410B §4.2.1/§4.2.2, the same programming error: an advance before the output
// (`Chip::advance_before_output`) during which the first AT's data enable the header ahead
// does not keep the bound found before: after every advance the chip's bound is the one a
// plain advance leaves, and the third telegram is still sent at its bound.
#[test]
fn data_over_a_header_ahead_are_not_outlived_by_a_kept_bound() {
    let (mut m, own, kept, word0) = header_ahead_run(true);
    assert!(kept > 10, "{kept} advances before the output");
    assert!(own.len() >= 3, "{own:?}");
    assert_eq!(m.read_ram(37), word0, "AT 1 stored over it");
}

// 410B §4.2.1 EN: the host enables a transmit header ahead of the current receive header
// (a RAM write through the bus): what the bound walked before must not survive it (found
// by fuzz target bus_sequence: a host RAM write kept the remembered walk).
#[test]
fn a_host_write_to_a_header_ahead_drops_the_remembered_walk() {
    let v = Variant::Sercon816;
    let (mut m, third) = master_with_a_header_ahead();
    // After the MST and the MDT the master waits for AT 1; nothing of its own is ahead in
    // this block (the header at 37 is off).
    m.advance_to(Instant::ZERO + Duration::from_micros(10));
    // Asked once: the walk ahead is remembered (debug builds check it on every use).
    let _ = m.next_output_bound();
    let enabled = TxHeader {
        en: TxEnable::Continuous,
        ..third
    };
    m.write_ram_words(37, &enabled.to_words(v));
    let after = m.next_output_bound();
    // The same chip built with the header on from the start (nothing remembered).
    let (mut fresh, _) = master_with_a_header_ahead();
    fresh.write_ram_words(37, &enabled.to_words(v));
    fresh.advance_to(Instant::ZERO + Duration::from_micros(10));
    assert_eq!(after, fresh.next_output_bound());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(32)))]

    // Any pair shape (cycle, telegram times, fibre delay, the master repeating too).
    #[test]
    fn any_pair_keeps_its_promises(shape in any_shape()) {
        let mut pair = chips(shape);
        let seen = run(
            &mut pair,
            Duration::from_nanos(shape.delay_ns),
            Instant::ZERO + Duration::from_micros(300),
        );
        prop_assert!(seen.released[1] > 4, "{:?}", seen);
    }

    // Arbitrary RAM (headers, containers and service containers anywhere, overlapping) and
    // arbitrary frames: the bound never panics and no own telegram starts before it; the
    // same with every advance that stops before the bound made by
    // `Chip::advance_before_output` (debug builds check every kept bound against a fresh
    // walk; the chip ends each step as a plain advance leaves it).
    #[test]
    fn arbitrary_ram_and_frames_keep_the_promise(
        ram in proptest::collection::vec(any::<u16>(), 64),
        fill in any::<u16>(),
        master in any::<bool>(),
        frames in any_frames(),
    ) {
        let chip = common::arbitrary_chip(&ram, fill, master, None);
        arbitrary_run(chip.clone(), frames.clone(), false)?;
        arbitrary_run(chip, frames, true)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("OUTPUT_BOUND_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(48)))]

    // 410B §4.2.1 (headers walked from COMPT0/1 along PT), §4.1 0AH PHAS, 0CH.2-3 COMBLK0/1:
    // arbitrary RAM and frames as above, and a host that writes headers, containers,
    // COMPT0/1, the phases and the block selection at any µs, a block running or not: the
    // promise asked after each write holds for every segment released, and every advance
    // before the bound (`Chip::advance_before_output`) leaves the chip a plain advance
    // leaves (debug builds check every kept bound and layout proof against fresh ones).
    #[test]
    fn host_writes_between_steps_keep_the_promise(
        ram in proptest::collection::vec(any::<u16>(), 64),
        fill in any::<u16>(),
        master in any::<bool>(),
        frames in any_frames(),
        writes in proptest::collection::vec(
            (0u64..300, 0u8..8, any::<u16>(), any::<u16>()),
            0..16,
        ),
    ) {
        let chip = common::arbitrary_chip(&ram, fill, master, None);
        arbitrary_run_with_writes(chip.clone(), frames.clone(), writes.clone(), false)?;
        arbitrary_run_with_writes(chip, frames, writes, true)?;
    }
}

// 410B §4.2.1 (a block's headers are walked from COMPT0/1, TRT counts from its start): a
// receive telegram still arriving when the next block is due may yet write data, VAL and
// NERR, so that block's walk is held at its start; a kept bound was that held start after
// the telegram had ended, where a fresh walk finds the first transmit telegram later (found by
// `arbitrary_ram_and_frames_keep_the_promise`, spec-notes "Held block walks"). Debug
// builds check every kept bound against a fresh walk.
#[test]
fn a_telegram_outliving_its_block_does_not_leave_its_held_bound_kept() {
    let mut ram = vec![0u16; 64];
    ram[0] = 41530;
    let mut bytes = vec![0u8; 26];
    bytes[12] = 175;
    bytes[13] = 124;
    let chip = common::arbitrary_chip(&ram, 55241, true, None);
    arbitrary_run(chip.clone(), vec![(284, bytes.clone())], false).expect("plain advances");
    arbitrary_run(chip, vec![(284, bytes)], true).expect("kept bounds");
}

/// Up to 12 frames of up to 40 bytes (ADR and data), each with its start in µs (0-299).
fn any_frames() -> impl Strategy<Value = Vec<(u64, Vec<u8>)>> {
    proptest::collection::vec(
        (0u64..300, proptest::collection::vec(any::<u8>(), 0..40)),
        0..12,
    )
}

/// Runs `chip` µs by µs to 400 µs with `frames` (start in µs, ADR and data) handed over a µs
/// ahead of their start (as a ring delivers them, 816 §2.3.1: 16 Mbit/s), checking every
/// released segment against the promise asked before its advance; with `keep`, every
/// advance that stops before the bound is `Chip::advance_before_output`, checked against a
/// plain advance of a copy.
fn arbitrary_run(chip: Chip, frames: Vec<(u64, Vec<u8>)>, keep: bool) -> Result<(), TestCaseError> {
    arbitrary_run_with_writes(chip, frames, Vec::new(), keep)
}

/// A host access between the steps of [`arbitrary_run_with_writes`]: at µs `t`, what `kind`
/// (0–7) says, with `addr` and `value`.
type HostWrite = (u64, u8, u16, u16);

/// The control word 0CH [`common::arbitrary_chip`] wrote (410B §4.1 0CH.0-1 MSTEN,
/// MSTMASTER; 0CH.10 CYCSTART).
fn ctrl0c(master: bool) -> u16 {
    if master {
        common::CTRL0C_MASTER | common::CTRL0C_CYCSTART
    } else {
        1
    }
}

/// Applies one [`HostWrite`] to `chip`, a `master` or a slave: kinds 0–4 a RAM word among the
/// first 128 (the headers, containers and pointers of an arbitrary RAM); 5 PHAS0/PHAS1
/// (410B §4.1 0AH); 6 the block selection bits 0CH.2-3 COMBLK0/1 (the rest as the chip was
/// started); 7 COMPT0/1 (410B §4.2 RAM words 0/1) to a word among the first 128.
fn host_write(chip: &mut Chip, master: bool, (_, kind, addr, value): HostWrite) {
    match kind {
        0..=4 => chip.write_ram(addr % 128, value),
        5 => chip.write(Register::Phas, value),
        6 => chip.write(Register::Ctrl0C, ctrl0c(master) | (value & 0b1100)),
        _ => chip.write_ram(addr & 1, value % 128),
    }
}

/// [`arbitrary_run`] with host writes (`writes`, at their µs, after the frames handed over
/// at that µs and before the promise is asked): the promise asked after a write holds too.
fn arbitrary_run_with_writes(
    mut chip: Chip,
    mut frames: Vec<(u64, Vec<u8>)>,
    mut writes: Vec<HostWrite>,
    keep: bool,
) -> Result<(), TestCaseError> {
    frames.sort_by_key(|f| f.0);
    writes.sort_by_key(|w| w.0);
    // 410B §4.1 0CH.1 MSTMASTER, as `common::arbitrary_chip` set it.
    let master = chip.read(Register::Ctrl0C) & 0b10 != 0;
    let mut buf = Vec::new();
    let mut next = frames.into_iter().peekable();
    let mut next_write = writes.into_iter().peekable();
    for t in 1..=400u64 {
        let now = Instant::ZERO + Duration::from_micros(t);
        while let Some((start, bytes)) = next.next_if(|f| f.0 <= t) {
            let start = Instant::ZERO + Duration::from_micros(start + 1);
            if let Some(seg) = common::try_hinted_frame(start, &bytes) {
                chip.line_input(seg);
            }
        }
        while let Some(w) = next_write.next_if(|w| w.0 <= t) {
            host_write(&mut chip, master, w);
        }
        let p = promise(&chip);
        if keep && chip.next_output_bound().is_some_and(|b| b > now) {
            let mut plain = chip.clone();
            plain.advance_to(now);
            chip.advance_before_output(now);
            prop_assert_eq!(chip.next_output_bound(), plain.next_output_bound());
            prop_assert_eq!(chip.read_register(0x17), plain.read_register(0x17));
        } else {
            chip.advance_to(now);
        }
        chip.take_line_output(&mut buf);
        for seg in buf.drain(..) {
            prop_assert!(
                p.is_some_and(|p| seg.start >= p),
                "a segment at {:?} before the promise {:?}",
                seg.start,
                p
            );
        }
    }
    Ok(())
}

/// The second receive header of [`master_with_a_header_ahead`] (at 50), its PT leading to
/// the header at 37 or, with `skip_third`, straight to the end marker at 70.
fn at2_header(skip_third: bool) -> RxHeader {
    RxHeader {
        adr: 2,
        achk: true,
        trt: 60,
        tlen: 1,
        pt: if skip_third { 70 } else { 37 },
        ..RxHeader::default()
    }
}

/// The master of [`master_with_a_header_ahead`] after its MST and MDT, both ATs handed over
/// ahead as a ring hands them (each telegram with the filler after it), AT 1 carrying the
/// header at 37 with EN = 2 (words little-endian, 410B §4.2.2 POS). With `skip_third`
/// AT 2's PT leads to the end marker, so the header at 37 is on no list. Returns the master
/// and the start of its MST.
fn master_with_ats_ahead(skip_third: bool) -> (Chip, Instant) {
    let v = Variant::Sercon816;
    let (mut m, third) = master_with_a_header_ahead();
    m.write_ram_words(50, &at2_header(skip_third).to_words(v));
    let (_, at1_bytes) = at1_enabling(third);
    let mut buf = Vec::new();
    let mut mst_at = None;
    let mut t = Instant::ZERO;
    while mst_at.is_none() && t < Instant::ZERO + Duration::from_micros(300) {
        t += Duration::from_micros(1);
        m.advance_to(t);
        m.take_line_output(&mut buf);
        mst_at = buf
            .iter()
            .find(|s| matches!(s.signal, LineSignal::Bits(_)))
            .map(|s| s.start);
        buf.clear();
    }
    let t0 = mst_at.expect("the master sends its MST");
    m.advance_to(t0 + Duration::from_micros(5));
    m.take_line_output(&mut buf);
    let with_filler = |s: LineSegment| LineSegment {
        then_filler: true,
        ..s
    };
    m.set_implied_filler(true);
    m.line_input(with_filler(common::hinted_frame(
        t0 + Duration::from_micros(15),
        &at1_bytes,
    )));
    m.line_input(with_filler(common::hinted_frame(
        t0 + Duration::from_micros(35),
        &[2, 0xAA, 0x55],
    )));
    (m, t0)
}

// 410B §4.2.1/§4.2.2, the same programming error, as a simulation sleeping on the promise
// sees it: both ATs handed over before the master reached them, then advances from promise
// to promise. AT 1's data enable the header ahead, so no promise may lie past the third
// telegram (the processor's own writes can rewrite its list: no layout proof).
#[test]
fn a_promise_made_with_frames_pending_holds_for_what_they_write() {
    let (mut m, t0) = master_with_ats_ahead(false);
    // The third telegram (TRT 120 µs after the MST's end), before the next MST (250 µs).
    sends_in_the_cycle(&mut m, t0);
}

// 410B §4.2.2: with AT 1's container laid over a header on the list nothing is promised
// beyond the master's next event (the frame waiting to be stored); with that header off the
// list the master sleeps through both frames to its next cycle.
#[test]
fn a_list_its_own_writes_can_rewrite_is_promised_nothing_beyond_the_next_event() {
    let (mut m, t0) = master_with_ats_ahead(false);
    // At AT 1's start (the line's first light after the MDT is an event of its own).
    m.advance_to(t0 + Duration::from_micros(15));
    assert!(m.next_internal_event_at().is_some());
    assert_eq!(m.next_output_bound(), m.next_internal_event_at());
    let (mut m, t0) = master_with_ats_ahead(true);
    m.advance_to(t0 + Duration::from_micros(15));
    assert!(
        m.next_output_bound() > m.next_internal_event_at(),
        "{:?} {:?}",
        m.next_output_bound(),
        m.next_internal_event_at()
    );
}

// A host write leaves the layout proof as it was, made or refused, unless it writes a word
// the walks read (a header, a container control word, the pointer words): a data word keeps
// the promise, AT 2's PT led back to the header under AT 1's container takes it, and led
// away again gives it back.
#[test]
fn a_host_write_to_a_header_can_take_the_layout_proof_a_data_write_keeps() {
    let v = Variant::Sercon816;
    let (mut m, t0) = master_with_ats_ahead(true);
    m.advance_to(t0 + Duration::from_micros(15));
    let bound = m.next_output_bound();
    m.write_ram(57, 0xBEEF);
    assert_eq!(m.next_output_bound(), bound, "a data word");
    assert!(bound > m.next_internal_event_at());
    m.write_ram_words(50, &at2_header(false).to_words(v));
    assert_eq!(
        m.next_output_bound(),
        m.next_internal_event_at(),
        "AT 2's PT"
    );
    // A refusal stands through a data write and falls with the header's write back.
    m.write_ram(57, 0xCAFE);
    assert_eq!(
        m.next_output_bound(),
        m.next_internal_event_at(),
        "a data word"
    );
    m.write_ram_words(50, &at2_header(true).to_words(v));
    assert_eq!(m.next_output_bound(), bound, "AT 2's PT back");
}

/// [`sleep_on_promises`] from `t0` (an MST's start): `m` sends a telegram of its own within
/// that cycle (the third telegram the received data enable), the promises kept on the way.
fn sends_in_the_cycle(m: &mut Chip, t0: Instant) {
    let own = sleep_on_promises(m, t0);
    assert!(
        own.first()
            .is_some_and(|s| *s < t0 + Duration::from_micros(250)),
        "{own:?} after the MST at {t0:?}"
    );
}

/// Advances `m` from promise to promise (a simulation sleeping on it) until it sends a
/// telegram of its own or 300 µs after `t0`, checking that nothing starts before the promise
/// asked before each advance; the starts of its own telegrams.
fn sleep_on_promises(m: &mut Chip, t0: Instant) -> Vec<Instant> {
    let mut buf = Vec::new();
    let mut own = Vec::new();
    while own.is_empty() && m.now() < t0 + Duration::from_micros(300) {
        let Some(p) = promise(m) else { break };
        m.advance_to(p);
        m.take_line_output(&mut buf);
        for seg in buf.drain(..) {
            assert!(
                seg.start >= p,
                "a segment at {:?} before the promise {p:?}",
                seg.start
            );
            if let LineSignal::Bits(_) = seg.signal {
                own.push(seg.start);
            }
        }
    }
    own
}

/// ERRATA "telegram header marker bits": 10 is no structure (the processor stops there,
/// 410B §4.1 17H PROGERR_FL bit 1).
const NO_HEADER: u16 = 0x8000;

// 410B §4.2.1/§4.2.2, ERRATA "telegram header marker bits": AT 2's PT leads to a word that is
// no header yet (marker bits 10) and AT 1's container lies over it; AT 1's data make it the
// enabled transmit header. The layout proof reads the word that decides whether a header is
// there: the data written over it can rewrite the list, so no promise lies past the
// third telegram (without reading it the proof held and the master promised its next cycle).
#[test]
fn data_over_a_word_that_is_no_header_yet_take_the_layout_proof() {
    let (mut m, t0) = master_with_ats_ahead(false);
    m.write_ram(37, NO_HEADER);
    sends_in_the_cycle(&mut m, t0);
}

// 410B §4.2.1, the same list with AT 2's PT leading to a word that is no header (marker bits
// 10, at 80): the proof holds (AT 1's container lies over the header at 37, on no list).
// A host write that makes a header of that word (EN = 0, PT → 37) writes a word the proof
// read: the proof kept from before is dropped, and AT 1's data, which enable the header at
// 37 now on the list, take it (without reading that word the kept proof promised the next
// cycle and the third telegram came before it).
#[test]
fn a_host_write_that_makes_a_header_of_a_word_drops_the_layout_proof() {
    let v = Variant::Sercon816;
    let (mut m, t0) = master_with_ats_ahead(false);
    m.write_ram_words(
        50,
        &RxHeader {
            pt: 80,
            ..at2_header(false)
        }
        .to_words(v),
    );
    m.write_ram(80, NO_HEADER);
    // At AT 1's start (the line's first light after the MDT is an event of its own).
    m.advance_to(t0 + Duration::from_micros(15));
    // The proof is made (and kept) with no header at 80.
    assert!(
        m.next_output_bound() > m.next_internal_event_at(),
        "{:?} {:?}",
        m.next_output_bound(),
        m.next_internal_event_at()
    );
    let header = TxHeader {
        adr: 4,
        en: TxEnable::Off,
        trt: 100,
        tlen: 1,
        pt: 37,
        ..TxHeader::default()
    };
    m.write_ram_words(84, &[control(1), 0x9ABC]);
    m.write_ram_words(80, &header.to_words(v));
    assert_eq!(m.next_output_bound(), m.next_internal_event_at());
    sends_in_the_cycle(&mut m, t0);
}

// 410B §4.2.1 PT, 816 §2.10.1.2 (the next header is read into NTH at the start of a telegram;
// its words are not read again): while AT 1 is being received the processor holds AT 2's
// header with PT → 37, the header AT 1's data enable. A host that then relinks AT 2's PT in
// the RAM to the end marker changes the list in the RAM, not the one the processor walks
// this cycle: the proof over the RAM's lists would hold (no list reaches 37), so the bound
// must not be promised while the header the processor holds differs from the RAM's.
#[test]
fn a_host_relinking_the_header_the_processor_holds_takes_the_layout_proof() {
    let v = Variant::Sercon816;
    let (mut m, t0) = master_with_ats_ahead(false);
    // Inside AT 1 (it starts 15 µs after the MST): AT 2's header is the current one.
    m.advance_to(t0 + Duration::from_micros(17));
    m.write_ram_words(50, &at2_header(true).to_words(v));
    assert_eq!(m.next_output_bound(), m.next_internal_event_at());
    // The processor went on from AT 2 to 37 (its header as read): the third telegram.
    sends_in_the_cycle(&mut m, t0);
}

// 410B §4.2.1 EN ("Transmit telegram enable": 0 sends nothing; EN is read into NTH with the
// header and not read again at the start, 410B §4.2.2). A master whose list has a receive
// header without TCHK and then a transmit header with EN = 0: a bound kept from the walk
// (which skips disabled transmit headers) was later than a fresh one taken once the receive
// telegram came and the disabled header was current (its start counted as a possible
// output): a debug check "kept out_bound" failed (a 1000-case soak of
// `host_writes_between_steps_keep_the_promise`). A current transmit telegram with EN = 0 now
// bounds as the walk does, by the next enabled one.
#[test]
fn a_current_transmit_header_with_en_0_bounds_as_the_walk_does() {
    let mut ram = vec![0u16; 64];
    ram[1] = 61200;
    ram[7] = 830;
    ram[27] = 32768;
    let frames = vec![
        (277, vec![1, 14, 88, 18, 107, 90, 198, 175]),
        (
            254,
            vec![
                6, 25, 36, 76, 5, 190, 0, 0, 40, 81, 7, 2, 12, 10, 0, 6, 3, 139, 70, 133, 130, 92,
                13, 69, 4, 122, 61, 10, 64, 46, 90, 6, 0, 1, 0, 52, 19, 173,
            ],
        ),
        (223, vec![15, 41, 87]),
        (224, vec![195, 29, 1, 29, 97, 228, 73, 144, 106]),
    ];
    let chip = common::arbitrary_chip(&ram, 865, true, None);
    arbitrary_run_with_writes(chip.clone(), frames.clone(), vec![(223, 6, 0, 396)], false)
        .expect("plain advances");
    arbitrary_run_with_writes(chip, frames, vec![(223, 6, 0, 396)], true).expect("kept bounds");
}

/// A master whose list is COMPT0 → MDT (TRT 2, EN = `mdt_en`) → AT 1 (TRT 20, TCHK: missing
/// when its window closes, nothing is sent to it) → a transmit header (TRT 60, EN = 1) → end
/// marker, in a 125 µs cycle.
fn master_with_headers_sent_once(mdt_en: TxEnable) -> Chip {
    let v = Variant::Sercon816;
    let mut m = Chip::new(ChipConfig::sercon816());
    m.write(Register::MclkDiv, 15);
    m.write(Register::Tscyc0, 250);
    let c1 = m.read(Register::Ctrl1);
    m.write(Register::Ctrl1, c1 & !(1 << 3));
    let mdt = TxHeader {
        adr: 255,
        en: mdt_en,
        trt: 2,
        tlen: 1,
        pt: 30,
        ..TxHeader::default()
    };
    m.write_ram(0, 16);
    m.write_ram_words(16, &mdt.to_words(v));
    m.write_ram_words(20, &[control(1), 0x1234]);
    let at1 = RxHeader {
        adr: 1,
        achk: true,
        tchk: true,
        trt: 20,
        tlen: 1,
        pt: 50,
        ..RxHeader::default()
    };
    m.write_ram_words(30, &at1.to_words(v));
    m.write_ram_words(35, &[control(1), 0, 0]);
    let once = TxHeader {
        adr: 3,
        en: TxEnable::Once,
        trt: 60,
        tlen: 1,
        pt: 70,
        ..TxHeader::default()
    };
    m.write_ram_words(50, &once.to_words(v));
    m.write_ram_words(54, &[control(1), 0x5678]);
    m.write_ram_words(70, &EndMarker::default().to_words());
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, 1 << 8);
    m.write(Register::Ctrl0C, 0b11 | (1 << 10));
    m
}

/// Runs [`master_with_headers_sent_once`] µs by µs for 370 µs (three cycles), every segment
/// checked against the promise asked before its advance; returns the starts of its own
/// telegrams and the promise asked at the first µs 10 µs or more into each cycle (its first
/// telegram, the MST, starts it).
fn sent_once_run(mdt_en: TxEnable) -> (Vec<Instant>, Vec<Option<Instant>>) {
    let cycle = Duration::from_micros(125);
    let mut m = master_with_headers_sent_once(mdt_en);
    let mut buf = Vec::new();
    let mut own = Vec::new();
    let mut ask_at = None;
    let mut asked = Vec::new();
    for t in 1..=370u64 {
        let now = Instant::ZERO + Duration::from_micros(t);
        let p = promise(&m);
        if let Some(a) = ask_at
            && now >= a
        {
            asked.push(p);
            ask_at = Some(a + cycle);
        }
        m.advance_to(now);
        m.take_line_output(&mut buf);
        for seg in buf.drain(..) {
            assert!(
                p.is_some_and(|p| seg.start >= p),
                "a segment at {:?} before the promise {p:?}",
                seg.start
            );
            if let LineSignal::Bits(_) = seg.signal {
                ask_at.get_or_insert(seg.start + Duration::from_micros(10));
                own.push(seg.start);
            }
        }
    }
    (own, asked)
}

// 410B §4.2.1 EN = 1 ("the circuit sets EN to 0 after the transmit telegram has been
// started"), TRT; §4.2 COMPT0: the walks ahead of a receive header and from COMPT are kept
// from one block to the next under the layout proof (`output_bound::TxAhead`, `BlockAhead`),
// but a header sent once is off in the next block: the walks that found it go with that
// write. In the first cycle the master sends its MST, the MDT and the header after AT 1; in
// the next two its MST (and the MDT when it is on), and 10 µs into them, AT 1 current, it
// promises nothing before the next cycle's MST (debug builds compare every kept walk with a
// fresh one).
#[test]
fn a_header_sent_once_is_not_promised_again_by_a_kept_walk() {
    for mdt_en in [TxEnable::Continuous, TxEnable::Once] {
        let (own, asked) = sent_once_run(mdt_en);
        let per_cycle = if mdt_en == TxEnable::Once { 1 } else { 2 };
        assert_eq!(own.len(), 3 + 2 * per_cycle, "{mdt_en:?}: {own:?}");
        let cycle = Duration::from_micros(125);
        let first = own[0];
        assert_eq!(asked.len(), 3, "{asked:?}");
        for (k, p) in asked.iter().enumerate().skip(1) {
            let next_mst = first + cycle.saturating_mul(k as u64 + 1);
            assert!(
                p.is_some_and(|p| p >= next_mst),
                "{mdt_en:?}, cycle {k}: promised {p:?}, next MST at {next_mst:?}"
            );
        }
    }
}
