//! Telegram-processor events that only raise a flag and set status: the opening of a receive
//! window (410B §4.1 4H.12 INT_RWAIT, 3H.10 FLRWAIT, 23H/24H THWPT/THW; §4.2.1 TCHK with
//! 18H/19H JTRDEL1/2), the end of a transmit telegram (4H.11 INT_TEND, 3H.9 FLTMT) and the
//! end marker (§4.2.3 TEND, 4H.4 INT_COMEND, 3H.6 COMACT) are events of their own only when
//! an enabled interrupt output carries their flag; otherwise the chip applies them with its
//! next telegram-processor event or bus access (spec-notes "Events nobody sees at once").
//! Both ways must read the same at every instant.

mod common;
mod harness;

use harness::*;
use sercon_regs::ram::header::TxEnable;
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};

/// 410B §4.1 3H.1 ENINT0.
const ENINT0: u16 = 1 << 1;
/// 410B §4.1 4H.4 INT_COMEND, 4H.11 INT_TEND, 4H.12 INT_RWAIT.
const QUIET_FLAGS: u16 = (1 << 4) | (1 << 11) | (1 << 12);
/// 410B §4.1 3H.6 COMACT, 3H.7 COMBLK, 3H.9 FLTMT, 3H.10 FLRWAIT, 3H.11 FLREC.
const FLAGS_3H: u16 = (1 << 6) | (1 << 7) | (1 << 9) | (1 << 10) | (1 << 11);

/// Phase 4, one slave: MDT (8 words) at TRT 5, AT (8 words) at TRT 40, cycle 100 µs; both
/// receive headers check their time (TCHK, JTRDEL1 = 2, JTRDEL2 = 3). With `int_out` both
/// chips enable INT0 for INT_RWAIT, INT_TEND and INT_COMEND (those events are then events
/// of their own).
fn ring(int_out: bool) -> Ring {
    let v = Variant::Sercon816;
    let mut m = chip(v);
    let mut s = chip(v);
    one_slave_blocks(&mut m, &mut s, true);
    for c in [&mut m, &mut s] {
        if int_out {
            c.write(Register::En0IntLo, QUIET_FLAGS);
        }
    }
    let int = if int_out { ENINT0 } else { 0 };
    s.write(Register::Phas, 0xFF04);
    s.write(Register::Ctrl3, ENTMT | int);
    s.write(Register::Ctrl0C, MSTEN);
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, ENTMT | int);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    Ring::new(m, s)
}

/// `f` on the ring with the interrupt output (the events are events) and on the one without
/// (they are applied quietly), in that order.
fn on_both<T>(mut f: impl FnMut(Ring) -> T) -> [T; 2] {
    [f(ring(true)), f(ring(false))]
}

/// What a host sees of those events: COMACT, COMBLK, FLTMT, FLRWAIT, FLREC (3H), the
/// flags (4H), THWPT, THW, and the TEND word of the end marker at `end`.
fn view(c: &mut sercon_model::Chip, end: u16) -> [u16; 5] {
    [
        c.read(Register::Ctrl3) & FLAGS_3H,
        c.read(Register::IntFlagsLo),
        c.read(Register::Thwpt),
        c.read(Register::Thw),
        c.read_ram(end + 1),
    ]
}

/// Runs both rings to each instant of `at` and compares what the hosts read then.
fn same_views(at: impl Iterator<Item = u64>) {
    let (mut event, mut folded) = (ring(true), ring(false));
    for t in at {
        let t = sercos_wire::time::Instant::ZERO + sercos_wire::time::Duration::from_nanos(t);
        event.run_to(t);
        folded.run_to(t);
        assert_eq!(
            view(&mut event.master, 44),
            view(&mut folded.master, 44),
            "master at {t:?}"
        );
        assert_eq!(
            view(&mut event.slave, 44),
            view(&mut folded.slave, 44),
            "slave at {t:?}"
        );
    }
    assert_eq!(event.log, folded.log, "the same telegrams");
}

// 410B §4.1 3H, 4H, 23H/24H, §4.2.3 TEND: read every 250 ns (inside every window, before
// and after each telegram starts and ends, around each end marker) the hosts see the same
// whether those were events or not.
#[test]
fn quiet_events_read_the_same_at_every_instant() {
    same_views((250..=320_000).step_by(250));
}

// The same read rarely: they are applied by the processor's next event (a frame start, a
// window's close, the next block), not by a bus access.
#[test]
fn quiet_events_read_the_same_when_applied_by_the_next_event() {
    same_views((37_000..=410_000).step_by(37_000));
}

// Without an interrupt output for INT_RWAIT the opening is no event. The slave's first
// MST ends at 4.06 µs; its MDT window opens 3 µs later (TRT 5 − JTRDEL1 2) and closes at
// 12.06 µs (TRT + JTRDEL2 3); the MDT reaches the slave after 8 µs. At 4.5 µs the slave
// is next due at the opening with the interrupt output, at the close without.
#[test]
fn the_opening_is_an_event_only_with_an_interrupt_output_for_it() {
    let at =
        |ns: u64| sercos_wire::time::Instant::ZERO + sercos_wire::time::Duration::from_nanos(ns);
    let next = on_both(|mut r| {
        r.run_to(at(4_500));
        r.slave.next_internal_event_at()
    });
    let ps = |ps: u64| Some(sercos_wire::time::Instant::from_picos(ps));
    assert_eq!(next, [ps(7_062_500), ps(12_062_500)]);
}

// A host that rewrites the expected header's first word after the window opened reads THW
// as it was at the opening (410B §4.1 24H THW: the header of the telegram waited for). The
// second cycle's MDT window opens at 107.06 µs, the MDT starts at 109.06 µs.
#[test]
fn a_header_written_after_the_opening_leaves_thw_as_it_was() {
    let seen = on_both(|mut r| {
        r.run_to(us(104));
        let before = r.slave.read_ram(16);
        r.run_to(us(107) + sercos_wire::time::Duration::from_nanos(500));
        r.slave.write_ram(16, before ^ 0x0001);
        let thw = (r.slave.read(Register::Thwpt), r.slave.read(Register::Thw));
        (before, thw)
    });
    assert_eq!(seen[0], seen[1]);
    assert_eq!(
        seen[1].1,
        (16, seen[1].0),
        "THWPT, THW: the slave's MDT header at the opening"
    );
}

// The slave's AT starts at 44.06 µs (TRT 40 after the MST's end) and ends at 54.56 µs,
// its end marker with it. At 50 µs the slave is next due at the AT's end with the interrupt
// output; without it nothing is due until the next MST arrives (after 100 µs).
#[test]
fn a_transmit_end_and_the_end_marker_are_events_only_with_an_interrupt_output() {
    let next = on_both(|mut r| {
        r.run_to(us(50));
        r.slave.next_internal_event_at()
    });
    let end = sercos_wire::time::Instant::from_picos(54_562_500);
    assert_eq!(next[0], Some(end));
    assert!(next[1].is_none_or(|n| n > us(100)), "{:?}", next[1]);
}

// A host that writes the end marker's TEND word after the block ended (no event) keeps what
// it wrote: the marker's TEND went in before the write (410B §4.2.3).
#[test]
fn a_host_write_after_a_quiet_end_marker_stays() {
    let seen = on_both(|mut r| {
        r.run_to(us(60));
        r.slave.write_ram(45, 0x1234);
        r.run_to(us(61));
        r.slave.read_ram(45)
    });
    assert_eq!(seen, [0x1234, 0x1234]);
}

// A host that only reads the RAM sees the TEND of an end marker passed (410B §4.2.3 TEND:
// "Time after end of MST at which the last telegram has ended", here the AT's end).
#[test]
fn a_ram_read_sees_the_tend_of_a_quiet_end_marker() {
    let seen = on_both(|mut r| {
        r.run_to(us(60));
        r.slave.read_ram(45)
    });
    assert_eq!(seen[0], seen[1]);
    assert_eq!(seen[1], 51, "TEND: the AT ends 50.5 µs after the MST's end");
}

// A reset keeps the RAM (410B §2 RSTN): the TEND of an end marker passed before it is
// there afterwards.
#[test]
fn a_reset_keeps_the_tend_of_a_quiet_end_marker() {
    let seen = on_both(|mut r| {
        r.run_to(us(60));
        r.slave.set_rstn(false);
        r.slave.set_rstn(true);
        r.slave.read_ram(45)
    });
    assert_eq!(seen, [51, 51]);
}

// Nobody reads for three cycles: the quiet events are applied by the processor's own next
// events only (a block must have ended before the next one starts, 410B §4.2.3, or it is an
// overlap in 17H PROGERR_FL), and the hosts then read the same, PROGERR_FL and 5H included.
#[test]
fn quiet_events_applied_by_the_processor_alone_read_the_same() {
    let (mut event, mut folded) = (ring(true), ring(false));
    event.run_to(us(350));
    folded.run_to(us(350));
    for (a, b, end) in [
        (&mut event.master, &mut folded.master, 44),
        (&mut event.slave, &mut folded.slave, 44),
    ] {
        assert_eq!(view(a, end), view(b, end));
        for r in [Register::ProgerrFl, Register::IntFlagsHi] {
            assert_eq!(a.read(r), b.read(r), "{r:?}");
        }
        assert_eq!(a.read(Register::ProgerrFl), 0, "the RAM layout is sound");
    }
    assert_eq!(event.log, folded.log, "the same telegrams");
}

// Found by fuzz target `quiet_events`: the chip reached the opening's tick in one advance
// (with the interrupt output it opened the window then); a frame delivered afterwards that
// starts at that very tick comes after the opening, so INT_RWAIT, THWPT and THW read the
// same (410B §4.1 4H.12, 23H/24H).
#[test]
fn a_frame_delivered_at_a_tick_already_reached_comes_after_the_opening() {
    let seen = on_both(|r| {
        let mut s = r.slave;
        s.line_input(common::hinted_frame(us(1), &[255, 4]));
        // The MST ends at 4.06 µs; the MDT window opens at 7.0625 µs.
        let open = sercos_wire::time::Instant::from_picos(7_062_500);
        s.advance_to(open);
        let mut mdt = vec![255u8];
        mdt.extend(std::iter::repeat_n(0x5A, 16));
        s.line_input(common::hinted_frame(open, &mdt));
        s.advance_to(us(30));
        view(&mut s, 44)
    });
    assert_eq!(seen[0], seen[1]);
    assert_ne!(seen[1][1] & (1 << 12), 0, "INT_RWAIT");
}

// A CYC_CLK edge at the instant the chip's block ended (410B §4.1 0CH.8 ENCYCCLK: the edge
// starts a cycle, and without MSTEN the block with it, §4.2): the end marker of that tick
// came first, whether it was an event or not, so the new block finds the old one ended
// (no overlap in 17H PROGERR_FL).
#[test]
fn a_cyc_clk_edge_at_a_tick_already_reached_comes_after_the_end_marker() {
    let mut seen = Vec::new();
    let mut end = None;
    for int_out in [true, false] {
        let mut c = chip(Variant::Sercon816);
        // COMPT0 → tx (TRT 5 µs, one word) → end marker.
        c.write_ram(0, 16);
        tx_header(&mut c, 16, tx(1, TxEnable::Continuous, 5, 1, 22));
        c.write_ram_words(20, &[control(1, true), 0x1234]);
        end_marker(&mut c, 22);
        if int_out {
            c.write(Register::En0IntLo, QUIET_FLAGS);
        }
        c.write(Register::Ctrl3, ENTMT | if int_out { ENINT0 } else { 0 });
        // 0CH.8 ENCYCCLK, NCYC = 1 (bits 12-15): one cycle per rising edge.
        c.write(Register::Ctrl0C, (1 << 8) | (1 << 12));
        c.set_cyc_clk(true);
        c.advance_to(us(6));
        // The end marker's tick: the transmit telegram's end (an event with the output).
        let end = *end.get_or_insert_with(|| {
            c.next_internal_event_at()
                .expect("the telegram's end on the chip with the output")
        });
        c.advance_to(end);
        c.set_cyc_clk(false);
        c.set_cyc_clk(true);
        c.advance_to(us(60));
        seen.push((end, view(&mut c, 22), c.read(Register::ProgerrFl)));
    }
    assert_eq!(seen[0], seen[1]);
    assert_eq!(seen[1].2, 0, "no overlap");
}
