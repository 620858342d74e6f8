//! Property: chips whose quiet cycle ends are no events of their own (`Chip::set_quiet_cycle_ends`,
//! on by default: a cycle end that raises no flag, ends no DIV_CLK pulse and starts no next
//! cycle is applied where the cycle state is next read) emit the same pin events, send the
//! same telegrams and read the same as chips whose timing control takes every cycle end as a
//! step, whatever NCYC, TSCYC, TINT0–3, DIV_CLK, ENTMT / MSTEN and the interrupt enables say,
//! whether a slave's cycle ends before, at or after its next MST and whatever the hosts read
//! (TCNT by RDCNT, COMACT / COMBLK, the flags) or write meanwhile (spec-notes "Quiet cycle
//! ends"; 410B §4.1 3H.6-7, 4H.2-4, 0CH, 0FH–14H, 1AH–20H; §4.2.1 TRT). Likewise slaves whose
//! MSTs start the next cycle the short way once the last one ended (`Chip::set_short_cycle_syncs`,
//! on by default) against slaves that always take the general way, with the hosts also writing
//! TINT0 / TINT1 and the phases between cycles and the frames arriving up to 120 µs ahead
//! (spec-notes "Short cycle syncs").

mod common;
mod harness;

use harness::*;
use proptest::prelude::*;
use sercon_model::Chip;
use sercon_model::pins::{Pin, PinEvent, PinSet};
use sercon_regs::ram::header::TxEnable;
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 3H.1 ENINT0, 3H.4 ENINT1.
const ENINT0: u16 = 1 << 1;
const ENINT1: u16 = 1 << 4;
/// 410B §4.1 0CH.5 ENCONCLK, 0CH.11 RDCNT.
const ENCONCLK: u16 = 1 << 5;
const RDCNT: u16 = 1 << 11;
/// 410B §4.1 0CH.2 COMBLK0, 0CH.3 COMBLK1.
const COMBLK0: u16 = 1 << 2;
const COMBLK1: u16 = 1 << 3;
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
/// changes length mid-cycle, 410B §4.1 0EH), write TINT0 and TINT1 (1AH / 1BH: the cycle's
/// plan and CON_CLK's edges change), write PHAS0 (0AH: a master's MST then carries that
/// phase, a slave expects it).
#[derive(Debug, Clone, Copy)]
enum Act {
    Nothing,
    Look,
    Clear,
    Tscyc(u16),
    Retrigger,
    Watchdog(u16),
    Mclkdiv(u16),
    Tint(u16, u16),
    Phase(u8),
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
        1 => (prop_oneof![1 => Just(0u16), 2 => 0u16..140], 0u16..140)
            .prop_map(|(t0, t1)| Act::Tint(t0, t1)),
        1 => prop_oneof![3 => Just(4u8), 1 => 0u8..8].prop_map(Act::Phase),
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
        Act::Tint(t0, t1) => {
            c.write(Register::Tint0, t0);
            c.write(Register::Tint1, t1);
            None
        }
        Act::Phase(p) => {
            let phas = c.read(Register::Phas);
            c.write(Register::Phas, (phas & 0xFF00) | u16::from(p));
            None
        }
    }
}

/// How a ring's slave takes its MSTs: with `block1` it processes block 1 (0CH.2 COMBLK0 = 1)
/// and its TSCYC0 is `tscyc0` (TSCYC1 its cycle), so what it reads of the cycle in progress
/// at an MST (the block whose TSCYC times the next one, `crate::mst`) differs from what it
/// reads after the cycle ended; with `msttchk` it checks each MST's time (25H.10 MSTTCHK,
/// JTSCYC1/2 = 3). Its PHAS1 is 3 with COMBLK1 = 1 (0AH, 0CH.3): an MST of phase 3 starts
/// block 1, one of a phase other than 3 or PHAS0 none (INT_PHASERR).
#[derive(Debug, Clone, Copy)]
struct SlaveMst {
    block1: bool,
    tscyc0: u16,
    msttchk: bool,
}

/// The model's short ways compared: quiet cycle ends (`Chip::set_quiet_cycle_ends`) and
/// short cycle syncs (`Chip::set_short_cycle_syncs`).
#[derive(Debug, Clone, Copy)]
struct Ways {
    quiet: bool,
    short: bool,
}

/// Both short ways on (the default).
const ALL: Ways = Ways {
    quiet: true,
    short: true,
};

/// A master (NCYC `ncyc`, timing `mt`) and one slave (timing `st`; its TSCYC decides
/// whether its cycle ends before, at or after the next MST; MSTs as `sm` says) in phase 4,
/// with the short ways `ways`, fibres of `delay_us`.
fn ring(mt: &Timing, st: &Timing, sm: SlaveMst, ncyc: u16, ways: Ways, delay_us: u64) -> Ring {
    let v = Variant::Sercon816;
    let mut m = chip(v);
    let mut sl = chip(v);
    one_slave_blocks(&mut m, &mut sl, true);
    program(&mut m, mt);
    program(&mut sl, st);
    for c in [&mut m, &mut sl] {
        c.set_quiet_cycle_ends(ways.quiet);
        c.set_short_cycle_syncs(ways.short);
    }
    sl.write(Register::Phas, 0x0304);
    if sm.block1 {
        sl.write(Register::Tscyc0, sm.tscyc0);
    }
    if sm.msttchk {
        sl.write(Register::Jtscyc1, 3);
        sl.write(Register::Jtscyc2, 3);
        sl.write(Register::Thrpt, MSTTCHK);
    }
    let comblk0 = if sm.block1 { COMBLK0 } else { 0 };
    sl.write(Register::Ctrl0C, MSTEN | ENCONCLK | comblk0 | COMBLK1);
    m.write(Register::Phas, 0x0404);
    m.write(
        Register::Ctrl0C,
        MSTEN | MSTMASTER | ENCONCLK | (ncyc << 12) | CYCSTART,
    );
    let mut ring = Ring::new(m, sl);
    ring.delay = Duration::from_micros(delay_us);
    ring
}

/// Quiet cycle ends against ends as steps (fibres of 3 µs).
fn same_rings(
    mt: &Timing,
    st: &Timing,
    sm: SlaveMst,
    ncyc: u16,
    steps: &[(u64, Act, Act)],
) -> Result<(), TestCaseError> {
    let every = Ways {
        quiet: false,
        ..ALL
    };
    same_rings_as(mt, st, sm, ncyc, steps, every, 3)
}

/// Rings with both short ways against rings with the short ways `other`, fibres of
/// `delay_us`: the same pin events and host views at each step, the same telegrams.
fn same_rings_as(
    mt: &Timing,
    st: &Timing,
    sm: SlaveMst,
    ncyc: u16,
    steps: &[(u64, Act, Act)],
    other: Ways,
    delay_us: u64,
) -> Result<(), TestCaseError> {
    let (mut ours, mut theirs) = (
        ring(mt, st, sm, ncyc, ALL, delay_us),
        ring(mt, st, sm, ncyc, other, delay_us),
    );
    let mut t = 0;
    for (hop, am, asl) in steps {
        t += hop;
        ours.run_to(us(t));
        theirs.run_to(us(t));
        prop_assert_eq!(
            drain(&mut ours.master),
            drain(&mut theirs.master),
            "master by {} µs",
            t
        );
        prop_assert_eq!(
            drain(&mut ours.slave),
            drain(&mut theirs.slave),
            "slave by {} µs",
            t
        );
        prop_assert_eq!(apply(&mut ours.master, *am), apply(&mut theirs.master, *am));
        prop_assert_eq!(apply(&mut ours.slave, *asl), apply(&mut theirs.slave, *asl));
    }
    prop_assert_eq!(&ours.log, &theirs.log);
    prop_assert_eq!(host_view(&mut ours.master), host_view(&mut theirs.master));
    prop_assert_eq!(host_view(&mut ours.slave), host_view(&mut theirs.slave));
    Ok(())
}

/// Two rings run to each of the instants `at` (µs): their slaves' pin events and host views
/// the same at each, and the same telegrams in the end.
fn same_slaves_at(ours: &mut Ring, theirs: &mut Ring, at: impl Iterator<Item = u64>) {
    for t in at {
        ours.run_to(us(t));
        theirs.run_to(us(t));
        assert_eq!(
            drain(&mut ours.slave),
            drain(&mut theirs.slave),
            "by {t} µs"
        );
        assert_eq!(
            host_view(&mut ours.slave),
            host_view(&mut theirs.slave),
            "by {t} µs"
        );
    }
    assert_eq!(ours.log, theirs.log);
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
    fn short_cycle_syncs_in_a_ring_read_as_general_ones(
        mt in timing(Just(100u16)),
        // The slave's cycle ends before, at or after the next MST (100 µs apart).
        st in timing(prop_oneof![2 => Just(100u16), 1 => 20u16..100, 1 => 100u16..140]),
        sm in (any::<bool>(), 20u16..200, any::<bool>())
            .prop_map(|(block1, tscyc0, msttchk)| SlaveMst { block1, tscyc0, msttchk }),
        ncyc in prop_oneof![2 => Just(0u16), 1 => 1u16..5],
        quiet in any::<bool>(),
        // Frames up to 120 µs ahead: an advance may chain the processor's steps from one
        // MST past the cycle end it synchronised.
        delay_us in prop_oneof![2 => 1u64..8, 1 => 8u64..120],
        steps in proptest::collection::vec((1u64..40, act(), act()), 1..40),
    ) {
        let general = Ways { quiet, short: false };
        same_rings_as(&mt, &st, sm, ncyc, &steps, general, delay_us)?;
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

/// A slave synchronised by MSTs one master cycle apart takes each new cycle the short way
/// when its last one has ended (its TSCYC as long as the master's or shorter, its µs a
/// MCLK period shorter, 410B §4.1 0EH) and the general way when the MST cuts it short (its
/// TSCYC or its µs longer: the MST comes early); with only the offset-0 entries of the ring
/// of the bench, with CON_CLK rising at each start (TINT0 = 0, TINT1 later), with entries
/// after the start, with a DIV_CLK pulse at the start, with DIVCLKMODE = 1 (816 §2.7), with
/// the hosts writing TINT0 / TINT1 and TSCYC0 between cycles and the master sending another
/// phase for a while (410B §4.1 0AH: block 1 by PHAS1, then a phase error), with frames 3 µs
/// and 90 µs ahead. Each reads and emits as with the general way.
#[test]
fn short_cycle_syncs_of_a_steady_slave_read_as_general_ones() {
    let cases: [([u16; 4], (u16, u16, u16)); 5] = [
        ([0; 4], (0, 0, 0)),
        ([0, 50, 0, 0], (0, 0, 0)),
        ([7, 33, 0, 90], (0, 0, 0)),
        ([0; 4], (0, 0, 1)),
        ([0; 4], (0, 0, 0x202)),
    ];
    for (tint, divclk) in cases {
        for (tscyc, mclkdiv) in [(100, 31), (60, 31), (100, 30), (130, 31), (100, 32)] {
            for delay_us in [3, 90, 250] {
                let mt = Timing {
                    tscyc: 100,
                    tint,
                    divclk,
                    tcntst: 0,
                    en: [0xFFFF, 0, 0, 0xFFFF],
                    entmt: true,
                };
                let st = Timing { tscyc, ..mt };
                let steps: Vec<(u64, Act, Act)> = (1..=150)
                    .map(|i| {
                        let (am, asl) = match i % 40 {
                            1 => (Act::Nothing, Act::Mclkdiv(mclkdiv)),
                            5 => (Act::Phase(3), Act::Look),
                            9 => (Act::Phase(4), Act::Nothing),
                            13 => (Act::Nothing, Act::Tint(0, 20)),
                            17 => (Act::Phase(6), Act::Nothing),
                            21 => (Act::Phase(4), Act::Tint(tint[0], tint[1])),
                            25 => (Act::Nothing, Act::Tscyc(70)),
                            29 => (Act::Nothing, Act::Tscyc(tscyc)),
                            n if n % 4 == 0 => (Act::Look, Act::Look),
                            n if n % 4 == 2 => (Act::Clear, Act::Clear),
                            _ => (Act::Nothing, Act::Nothing),
                        };
                        (7, am, asl)
                    })
                    .collect();
                let sm = SlaveMst {
                    block1: false,
                    tscyc0: 100,
                    msttchk: true,
                };
                let general = Ways {
                    quiet: true,
                    short: false,
                };
                same_rings_as(&mt, &st, sm, 0, &steps, general, delay_us).unwrap_or_else(|e| {
                    panic!("TINT {tint:?}, DIV_CLK {divclk:?}, TSCYC {tscyc}, MCLKDIV {mclkdiv}, {delay_us} µs: {e}")
                });
            }
        }
    }
}

/// A chip that ran one cycle of its own (NCYC = 1, its plan built), triggered again
/// (CYCSTART after a long TCYCSTART, 410B §4.1 0CH.10, 0CH.12-15, 14H) and then made a slave
/// (MSTEN) before that start: its first MST synchronises it and the pending start is dropped
/// (`sync_cycle`; 410B §4.2.1 TRT), the general way, not the short one, which needs no start
/// pending.
#[test]
fn a_start_pending_at_a_slaves_first_mst_is_dropped_as_the_general_way_drops_it() {
    let t = Timing {
        tscyc: 100,
        tint: [0; 4],
        divclk: (0, 0, 0),
        tcntst: 0,
        en: [0xFFFF, 0xFFFF, 0, 0],
        entmt: true,
    };
    let sm = SlaveMst {
        block1: false,
        tscyc0: 100,
        msttchk: false,
    };
    let pending = |ways: Ways| {
        let mut r = ring(&t, &t, sm, 0, ways, 3);
        r.slave
            .write(Register::Ctrl0C, ENCONCLK | (1 << 12) | CYCSTART);
        r.run_to(us(150));
        r.slave.write(Register::Tcycstart, 1000);
        r.slave
            .write(Register::Ctrl0C, ENCONCLK | (1 << 12) | CYCSTART);
        r.slave.write(Register::Ctrl0C, MSTEN | ENCONCLK);
        r
    };
    let (mut ours, mut theirs) = (
        pending(ALL),
        pending(Ways {
            quiet: true,
            short: false,
        }),
    );
    same_slaves_at(&mut ours, &mut theirs, (160..=1500).step_by(10));
}

/// A slave that sends nothing (its AT header off, 410B §4.2.1 EN = 0; its repeater off) and
/// receives its frames
/// 250 µs ahead: one advance takes the processor's steps from an MST's end through the MDT
/// to the next MST's end as one chain (spec-notes "Chained processor steps"), past the quiet
/// end of the cycle the first MST started (its TSCYC as long as the master's, or shorter).
/// The chain applies that end before the next MST synchronises the slave (the short sync put
/// it in the timing control's memo), and reads and emits as with the general way.
#[test]
fn a_chain_from_one_mst_past_the_cycle_end_it_synchronised() {
    let mt = Timing {
        tscyc: 100,
        tint: [0; 4],
        divclk: (0, 0, 0),
        tcntst: 0,
        en: [0; 4],
        entmt: true,
    };
    let sm = SlaveMst {
        block1: false,
        tscyc0: 100,
        msttchk: true,
    };
    for tscyc in [30, 60, 100] {
        let st = Timing { tscyc, ..mt };
        let silent = |ways: Ways| {
            let mut r = ring(&mt, &st, sm, 0, ways, 250);
            tx_header(&mut r.slave, 31, tx(1, TxEnable::Off, 40, 8, 44));
            // 410B §4.1 1H.3 REPON = 0: nothing to forward either.
            let c1 = r.slave.read(Register::Ctrl1);
            r.slave.write(Register::Ctrl1, c1 & !REPON);
            r
        };
        let (mut ours, mut theirs) = (
            silent(ALL),
            silent(Ways {
                quiet: true,
                short: false,
            }),
        );
        same_slaves_at(&mut ours, &mut theirs, (1..=16).map(|i| i * 250));
    }
}
