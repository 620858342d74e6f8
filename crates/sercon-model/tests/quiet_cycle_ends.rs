//! Property: chips whose quiet cycle ends are no events of their own (`Chip::set_quiet_cycle_ends`,
//! on by default: a cycle end that raises no flag, ends no DIV_CLK pulse and starts no next
//! cycle is applied where the cycle state is next read) emit the same pin events, send the
//! same telegrams and read the same as chips whose timing control takes every cycle end as a
//! step, whatever NCYC, TSCYC, TINT0–3, DIV_CLK, ENTMT / MSTEN and the interrupt enables say,
//! whether a slave's cycle ends before, at or after its next MST and whatever the hosts read
//! (TCNT by RDCNT, COMACT / COMBLK, the flags) or write meanwhile (spec-notes "Quiet cycle
//! ends"; 410B §4.1 3H.6-7, 4H.2-4, 0CH, 0FH–14H, 1AH–20H; §4.2.1 TRT).

mod common;
mod harness;

use harness::*;
use proptest::prelude::*;
use sercon_model::Chip;
use sercon_model::pins::{Pin, PinEvent, PinSet};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 3H.1 ENINT0, 3H.4 ENINT1.
const ENINT0: u16 = 1 << 1;
const ENINT1: u16 = 1 << 4;
/// 410B §4.1 0CH.5 ENCONCLK, 0CH.11 RDCNT.
const ENCONCLK: u16 = 1 << 5;
const RDCNT: u16 = 1 << 11;
/// 410B §4.1 0CH.2 COMBLK0.
const COMBLK0: u16 = 1 << 2;
/// 816 §2.11.2 28H.0 WDOG_START, 28H.2 WDOUT_SET.
const WDOG_START: u16 = 1 << 0;
const WDOUT_SET: u16 = 1 << 2;

/// The timing settings of one chip: TSCYC0, TINT0–3, TDIVCLK, DTDIVCLK, NDIVCLK (with
/// DIVCLKMODE in bit 9), TCNTST, the interrupt enables of 6H–9H, ENTMT.
#[derive(Debug, Clone, Copy)]
struct Timing {
    tscyc: u16,
    tint: [u16; 4],
    divclk: (u16, u16, u16),
    tcntst: u16,
    en: [u16; 4],
    entmt: bool,
}

fn timing(tscyc: impl Strategy<Value = u16>) -> impl Strategy<Value = Timing> {
    let en = prop_oneof![3 => Just(0u16), 2 => any::<u16>(), 1 => Just(0xFFFF)];
    (
        tscyc,
        // Offset 0 (with TCNTST = 0) often: the cycle start's own entries.
        proptest::array::uniform4(prop_oneof![1 => Just(0u16), 3 => 0u16..140]),
        (
            prop_oneof![1 => Just(0u16), 3 => 0u16..140],
            0u16..30,
            prop_oneof![2 => Just(0u16), 1 => 0u16..4, 1 => 0x200u16..0x204],
        ),
        prop_oneof![3 => Just(0u16), 1 => any::<u16>()],
        proptest::array::uniform4(en),
        any::<bool>(),
    )
        .prop_map(|(tscyc, tint, divclk, tcntst, en, entmt)| Timing {
            tscyc,
            tint,
            divclk,
            tcntst,
            en,
            entmt,
        })
}

/// Every pin the engine drives, traced.
fn traced() -> PinSet {
    [Pin::Int0, Pin::Int1, Pin::ConClk, Pin::DivClk, Pin::Wdogn]
        .into_iter()
        .fold(PinSet::EMPTY, PinSet::with)
}

/// Writes `t` (but TSCYC0 and TCNTST, which a ring's slave must not move off the master's
/// when `keep_cycle`) into `c`, with ENCONCLK and `ctrl0c`'s other bits in 0CH.
fn program(c: &mut Chip, t: &Timing) {
    c.write(Register::Tscyc0, t.tscyc);
    c.write(Register::Tscyc1, t.tscyc);
    c.write(Register::Tcntst, t.tcntst);
    for (r, v) in [
        Register::Tint0,
        Register::Tint1,
        Register::Tint2,
        Register::Tint3,
    ]
    .into_iter()
    .zip(t.tint)
    {
        c.write(r, v);
    }
    c.write(Register::Tdivclk, t.divclk.0);
    c.write(Register::Dtdivclk, t.divclk.1);
    c.write(Register::Ndivclk, t.divclk.2);
    c.write(Register::En0IntLo, t.en[0]);
    c.write(Register::En0IntHi, t.en[1]);
    c.write(Register::En1IntLo, t.en[2]);
    c.write(Register::En1IntHi, t.en[3]);
    let ints = if t.en[0] | t.en[1] != 0 { ENINT0 } else { 0 }
        | if t.en[2] | t.en[3] != 0 { ENINT1 } else { 0 };
    c.write(Register::Ctrl3, if t.entmt { ENTMT } else { 0 } | ints);
    c.set_traced_pins(traced());
}

/// What a host reads of the timing control and the interrupts (TCNT latched by RDCNT,
/// 410B §4.1 0CH.11 / 12H), and the RAM's first words.
fn host_view(c: &mut Chip) -> (Option<Instant>, Vec<u16>) {
    // The next observable instant (a probe of the timing control run ahead).
    let deadline = c.next_deadline();
    let c0c = c.read(Register::Ctrl0C);
    c.write(Register::Ctrl0C, c0c | RDCNT);
    let mut v: Vec<u16> = [
        Register::Tcntlt,
        Register::Ctrl3,
        Register::IntFlagsLo,
        Register::IntFlagsHi,
        Register::Tcycdel,
        Register::PhasRec,
    ]
    .into_iter()
    .map(|r| c.read(r))
    .collect();
    v.extend((0..48u16).map(|a| c.read_ram(a)));
    v.push(c.read(Register::WdogCtrl));
    (deadline, v)
}

fn drain(c: &mut Chip) -> Vec<PinEvent> {
    let mut out = Vec::new();
    c.drain_pin_events(&mut out);
    out
}

/// What a host does at one of the instants: look (read everything), clear every flag,
/// write a new TSCYC0 (mid-cycle: spec-notes "timing registers written mid-cycle"),
/// retrigger the timing control (CYCSTART; a slave ignores it), start the watchdog with
/// TWDOG and its output on (816 §2.6, 28H WDOG_START / WDOUT_SET, 2AH TWDOG; its expiry
/// clears ENTMT, which may make the next cycle end loud), write a new MCLKDIV (the µs
/// changes length mid-cycle, 410B §4.1 0EH).
#[derive(Debug, Clone, Copy)]
enum Act {
    Nothing,
    Look,
    Clear,
    Tscyc(u16),
    Retrigger,
    Watchdog(u16),
    Mclkdiv(u16),
}

fn act() -> impl Strategy<Value = Act> {
    prop_oneof![
        6 => Just(Act::Nothing),
        3 => Just(Act::Look),
        2 => Just(Act::Clear),
        1 => (20u16..140).prop_map(Act::Tscyc),
        1 => Just(Act::Retrigger),
        1 => (1u16..300).prop_map(Act::Watchdog),
        1 => (15u16..40).prop_map(Act::Mclkdiv),
    ]
}

fn apply(c: &mut Chip, a: Act) -> Option<(Option<Instant>, Vec<u16>)> {
    match a {
        Act::Nothing => None,
        Act::Look => Some(host_view(c)),
        Act::Clear => {
            c.write(Register::IntFlagsLo, 0xFFFF);
            c.write(Register::IntFlagsHi, 0xFFFF);
            None
        }
        Act::Tscyc(v) => {
            c.write(Register::Tscyc0, v);
            None
        }
        Act::Retrigger => {
            let c0c = c.read(Register::Ctrl0C);
            c.write(Register::Ctrl0C, c0c | CYCSTART);
            None
        }
        Act::Watchdog(twdog) => {
            c.write(Register::Twdog, twdog);
            c.write(Register::WdogCtrl, WDOG_START | WDOUT_SET);
            None
        }
        Act::Mclkdiv(v) => {
            c.write(Register::MclkDiv, v);
            None
        }
    }
}

/// How a ring's slave takes its MSTs: with `block1` it processes block 1 (0CH.2 COMBLK0 = 1)
/// and its TSCYC0 is `tscyc0` (TSCYC1 its cycle), so what it reads of the cycle in progress
/// at an MST (the block whose TSCYC times the next one, `crate::mst`) differs from what it
/// reads after the cycle ended; with `msttchk` it checks each MST's time (25H.10 MSTTCHK,
/// JTSCYC1/2 = 3).
#[derive(Debug, Clone, Copy)]
struct SlaveMst {
    block1: bool,
    tscyc0: u16,
    msttchk: bool,
}

/// A master (NCYC `ncyc`, timing `mt`) and one slave (timing `st`; its TSCYC decides
/// whether its cycle ends before, at or after the next MST; MSTs as `sm` says) in phase 4,
/// both quiet ends `quiet`.
fn ring(mt: &Timing, st: &Timing, sm: SlaveMst, ncyc: u16, quiet: bool) -> Ring {
    let v = Variant::Sercon816;
    let mut m = chip(v);
    let mut sl = chip(v);
    one_slave_blocks(&mut m, &mut sl, true);
    program(&mut m, mt);
    program(&mut sl, st);
    for c in [&mut m, &mut sl] {
        c.set_quiet_cycle_ends(quiet);
    }
    sl.write(Register::Phas, 0xFF04);
    if sm.block1 {
        sl.write(Register::Tscyc0, sm.tscyc0);
    }
    if sm.msttchk {
        sl.write(Register::Jtscyc1, 3);
        sl.write(Register::Jtscyc2, 3);
        sl.write(Register::Thrpt, MSTTCHK);
    }
    let comblk0 = if sm.block1 { COMBLK0 } else { 0 };
    sl.write(Register::Ctrl0C, MSTEN | ENCONCLK | comblk0);
    m.write(Register::Phas, 0x0404);
    m.write(
        Register::Ctrl0C,
        MSTEN | MSTMASTER | ENCONCLK | (ncyc << 12) | CYCSTART,
    );
    let mut ring = Ring::new(m, sl);
    ring.delay = Duration::from_micros(3);
    ring
}

fn same_rings(
    mt: &Timing,
    st: &Timing,
    sm: SlaveMst,
    ncyc: u16,
    steps: &[(u64, Act, Act)],
) -> Result<(), TestCaseError> {
    let (mut quiet, mut every) = (ring(mt, st, sm, ncyc, true), ring(mt, st, sm, ncyc, false));
    let mut t = 0;
    for (hop, am, asl) in steps {
        t += hop;
        quiet.run_to(us(t));
        every.run_to(us(t));
        prop_assert_eq!(
            drain(&mut quiet.master),
            drain(&mut every.master),
            "master by {} µs",
            t
        );
        prop_assert_eq!(
            drain(&mut quiet.slave),
            drain(&mut every.slave),
            "slave by {} µs",
            t
        );
        prop_assert_eq!(apply(&mut quiet.master, *am), apply(&mut every.master, *am));
        prop_assert_eq!(apply(&mut quiet.slave, *asl), apply(&mut every.slave, *asl));
    }
    prop_assert_eq!(&quiet.log, &every.log);
    prop_assert_eq!(host_view(&mut quiet.master), host_view(&mut every.master));
    prop_assert_eq!(host_view(&mut quiet.slave), host_view(&mut every.slave));
    Ok(())
}

/// One chip's timing control alone (no MST: MSTEN = 0, ENTMT as `t` says, NCYC `ncyc`),
/// started by CYCSTART after TCYCSTART `tcycstart`, advanced to instants `ps` picoseconds
/// apart (between MCLK edges too), with the host acting at each.
fn alone(t: &Timing, ncyc: u16, tcycstart: u16, quiet: bool) -> Chip {
    let mut c = common::chip816();
    program(&mut c, t);
    c.set_quiet_cycle_ends(quiet);
    c.write(Register::Tcycstart, tcycstart);
    c.write(Register::Ctrl0C, ENCONCLK | (ncyc << 12) | CYCSTART);
    c
}

fn same_alone(
    t: &Timing,
    ncyc: u16,
    tcycstart: u16,
    steps: &[(u64, Act)],
) -> Result<(), TestCaseError> {
    let (mut quiet, mut every) = (
        alone(t, ncyc, tcycstart, true),
        alone(t, ncyc, tcycstart, false),
    );
    let mut at = Instant::ZERO;
    for (ps, a) in steps {
        at += Duration::from_picos(*ps);
        quiet.advance_to(at);
        every.advance_to(at);
        prop_assert_eq!(drain(&mut quiet), drain(&mut every), "by {:?}", at);
        prop_assert_eq!(apply(&mut quiet, *a), apply(&mut every, *a), "by {:?}", at);
    }
    prop_assert_eq!(host_view(&mut quiet), host_view(&mut every));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(48)))]

    #[test]
    fn quiet_cycle_ends_in_a_ring_read_as_steps(
        mt in timing(Just(100u16)),
        // The slave's cycle ends before, at or after the next MST (100 µs apart).
        st in timing(prop_oneof![2 => Just(100u16), 1 => 60u16..100, 1 => 100u16..140]),
        sm in (any::<bool>(), 20u16..200, any::<bool>())
            .prop_map(|(block1, tscyc0, msttchk)| SlaveMst { block1, tscyc0, msttchk }),
        ncyc in prop_oneof![2 => Just(0u16), 1 => 1u16..5],
        steps in proptest::collection::vec((1u64..40, act(), act()), 1..40),
    ) {
        same_rings(&mt, &st, sm, ncyc, &steps)?;
    }

    #[test]
    fn quiet_cycle_ends_of_the_timing_control_alone_read_as_steps(
        t in timing(prop_oneof![1 => 1u16..10, 3 => 10u16..140]),
        ncyc in prop_oneof![1 => Just(0u16), 3 => 1u16..5],
        tcycstart in 0u16..20,
        steps in proptest::collection::vec(
            (
                prop_oneof![
                    1 => 1u64..100_000,
                    2 => 100_000u64..30_000_000,
                    1 => 30_000_000u64..300_000_000,
                ],
                act(),
            ),
            1..60,
        ),
    ) {
        same_alone(&t, ncyc, tcycstart, &steps)?;
    }
}

/// A slave in an intact ring whose cycle is as long as the master's: each of its cycles
/// ends on the tick its next MST synchronises it, quietly; it reads as with steps.
#[test]
fn a_slave_cycle_ending_at_its_next_mst_reads_as_a_step() {
    let t = Timing {
        tscyc: 100,
        tint: [7, 33, 0, 90],
        divclk: (0, 0, 0),
        tcntst: 0,
        en: [0xFFFF, 0, 0, 0xFFFF],
        entmt: true,
    };
    let steps: Vec<(u64, Act, Act)> = (1..=120)
        .map(|i| {
            let a = match i % 4 {
                0 => Act::Look,
                1 => Act::Clear,
                _ => Act::Nothing,
            };
            (7, a, a)
        })
        .collect();
    for sm in [
        SlaveMst {
            block1: false,
            tscyc0: 100,
            msttchk: true,
        },
        // Block 1 with another TSCYC0: the MST that ends the cycle times the next one's
        // window by the last cycle's block (spec-notes "MST window of the last cycle"), as
        // with the end a step before it.
        SlaveMst {
            block1: true,
            tscyc0: 60,
            msttchk: true,
        },
    ] {
        same_rings(&t, &t, sm, 0, &steps).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// The timing control's last cycle (NCYC = 1) ends quietly (ENTMT) and the watchdog expires
/// after it within the same advance: the end comes first, with ENTMT still set (no
/// INT_COMEND), as when it is a step; the expiry then clears ENTMT (816 §2.6.2).
#[test]
fn a_quiet_end_before_a_watchdog_expiry_in_the_same_advance() {
    let t = Timing {
        tscyc: 40,
        tint: [5, 6, 7, 8],
        divclk: (0, 0, 0),
        tcntst: 0,
        en: [0xFFFF, 0xFFFF, 0, 0],
        entmt: true,
    };
    for twdog in [30, 41, 50, 70] {
        let steps = [
            (1_000_000, Act::Watchdog(twdog)),
            (100_000_000, Act::Look),
            (1_000_000, Act::Look),
        ];
        same_alone(&t, 1, 0, &steps).unwrap_or_else(|e| panic!("TWDOG {twdog}: {e}"));
    }
}
