//! Property: chips that take the telegram processor's events one after the other without a
//! turn of their event loop in between (`Chip::set_chained_steps`, on by default) emit the
//! same pin events, send the same telegrams and read the same as chips that give every
//! event its own turn, whichever interrupt flags reach INT0 / INT1, however the timing
//! control interleaves its own events and however far ahead the frames arrive (spec-notes
//! "Chained processor steps"; 410B §4.1 3H, 4H–9H, 1AH–1DH TINT0–3, 0CH.5 ENCONCLK;
//! §4.2.1–§4.2.3).

mod common;
mod harness;

use harness::*;
use proptest::prelude::*;
use sercon_model::Chip;
use sercon_model::pins::{Pin, PinEvent, PinSet};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::Duration;

/// 410B §4.1 3H.1 ENINT0, 3H.4 ENINT1.
const ENINT0: u16 = 1 << 1;
const ENINT1: u16 = 1 << 4;
/// 410B §4.1 0CH.5 ENCONCLK.
const ENCONCLK: u16 = 1 << 5;

/// How both chips of a ring are set up: the interrupt enables of 6H–9H (INT0 lo / hi, INT1
/// lo / hi), TINT0–3 in µs, CON_CLK on, the receive windows checked (TCHK), the fibre
/// delay in µs (frames arrive that far ahead of the receiver's next advance; the ring
/// advances in steps of half of it), and whether the serial port's pins are traced too
/// (then their changes inside a telegram are events the loop takes between its start and
/// its end).
#[derive(Debug, Clone, Copy)]
struct Setup {
    en: [u16; 4],
    tint: [u16; 4],
    conclk: bool,
    tchk: bool,
    delay_us: u64,
    serial_pins: bool,
}

/// Phase 4, one slave: MDT (8 words) at TRT 5, AT (8 words) at TRT 40, cycle 100 µs (the
/// ring of tests/quiet_events.rs), every pin traced.
fn ring(s: Setup, chained: bool) -> Ring {
    let v = Variant::Sercon816;
    let mut m = chip(v);
    let mut sl = chip(v);
    one_slave_blocks(&mut m, &mut sl, s.tchk);
    let ints = if s.en[0] | s.en[1] != 0 { ENINT0 } else { 0 }
        | if s.en[2] | s.en[3] != 0 { ENINT1 } else { 0 };
    let conclk = if s.conclk { ENCONCLK } else { 0 };
    for c in [&mut m, &mut sl] {
        c.write(Register::En0IntLo, s.en[0]);
        c.write(Register::En0IntHi, s.en[1]);
        c.write(Register::En1IntLo, s.en[2]);
        c.write(Register::En1IntHi, s.en[3]);
        for (r, t) in [
            Register::Tint0,
            Register::Tint1,
            Register::Tint2,
            Register::Tint3,
        ]
        .into_iter()
        .zip(s.tint)
        {
            c.write(r, t);
        }
        c.write(Register::Ctrl3, ENTMT | ints);
        let pins = [
            Pin::Int0,
            Pin::Int1,
            Pin::ConClk,
            Pin::DivClk,
            Pin::Wdogn,
            Pin::LErrn,
        ]
        .into_iter()
        .fold(PinSet::EMPTY, PinSet::with);
        let serial = [Pin::Idle, Pin::Reactn, Pin::TxD];
        c.set_traced_pins(if s.serial_pins {
            serial.into_iter().fold(pins, PinSet::with)
        } else {
            pins
        });
        c.set_chained_steps(chained);
    }
    sl.write(Register::Phas, 0xFF04);
    sl.write(Register::Ctrl0C, MSTEN | conclk);
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART | conclk);
    let mut ring = Ring::new(m, sl);
    ring.delay = Duration::from_micros(s.delay_us);
    ring
}

/// What a host reads of the processor and the interrupts, and the RAM.
fn host_view(c: &mut Chip) -> Vec<u16> {
    let mut v: Vec<u16> = [
        Register::Ctrl3,
        Register::IntFlagsLo,
        Register::IntFlagsHi,
        Register::ProgerrFl,
        Register::Thtpt,
        Register::Tht,
        Register::Thwpt,
        Register::Thw,
        Register::Thrpt,
        Register::Thr,
    ]
    .into_iter()
    .map(|r| c.read(r))
    .collect();
    v.extend((0..64u16).map(|a| c.read_ram(a)));
    v
}

fn drain(c: &mut Chip) -> Vec<PinEvent> {
    let mut out = Vec::new();
    c.drain_pin_events(&mut out);
    out
}

/// Runs a ring with chained steps and one without to the instants `at` (µs), comparing
/// both chips' pin events at each and their host views where `looks` says; where `clears`
/// says, both hosts then clear every interrupt flag (ERRATA "410B 4H/5H": writing 1
/// clears), so that INT0 / INT1 fall and the next flag shows when it rises. At the end,
/// what was sent.
fn same_runs(s: Setup, at: &[u64], looks: u32, clears: u32) -> Result<(), TestCaseError> {
    let (mut chained, mut single) = (ring(s, true), ring(s, false));
    for (i, t) in at.iter().enumerate() {
        chained.run_to(us(*t));
        single.run_to(us(*t));
        prop_assert_eq!(
            drain(&mut chained.master),
            drain(&mut single.master),
            "master by {} µs",
            t
        );
        prop_assert_eq!(
            drain(&mut chained.slave),
            drain(&mut single.slave),
            "slave by {} µs",
            t
        );
        let bit = 1 << (i % 32);
        if looks & bit != 0 {
            prop_assert_eq!(
                host_view(&mut chained.master),
                host_view(&mut single.master)
            );
            prop_assert_eq!(host_view(&mut chained.slave), host_view(&mut single.slave));
        }
        if clears & bit != 0 {
            for r in [&mut chained, &mut single] {
                for c in [&mut r.master, &mut r.slave] {
                    c.write(Register::IntFlagsLo, 0xFFFF);
                    c.write(Register::IntFlagsHi, 0xFFFF);
                }
            }
        }
    }
    prop_assert_eq!(&chained.log, &single.log);
    prop_assert_eq!(
        host_view(&mut chained.master),
        host_view(&mut single.master)
    );
    prop_assert_eq!(host_view(&mut chained.slave), host_view(&mut single.slave));
    Ok(())
}

fn setup() -> impl Strategy<Value = Setup> {
    let en = prop_oneof![3 => Just(0u16), 2 => any::<u16>(), 1 => Just(0xFFFF)];
    (
        proptest::array::uniform4(en),
        proptest::array::uniform4(0u16..120),
        any::<bool>(),
        any::<bool>(),
        1u64..120,
        prop_oneof![3 => Just(false), 1 => Just(true)],
    )
        .prop_map(|(en, tint, conclk, tchk, delay_us, serial_pins)| Setup {
            en,
            tint,
            conclk,
            tchk,
            delay_us,
            serial_pins,
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(48)))]

    #[test]
    fn chained_steps_emit_and_read_as_single_steps(
        s in setup(),
        hops in proptest::collection::vec(1u64..30, 1..40),
        looks in any::<u32>(),
        clears in any::<u32>(),
    ) {
        let at: Vec<u64> = hops
            .iter()
            .scan(0, |t, h| {
                *t += h;
                Some(*t)
            })
            .collect();
        same_runs(s, &at, looks, clears)?;
    }
}

/// With no interrupt output the processor's events chain (nothing to settle between them);
/// with every flag on INT0 none does; both read as single steps.
#[test]
fn chained_steps_with_and_without_interrupt_outputs() {
    for (en, serial_pins) in [
        ([0; 4], false),
        ([0xFFFF, 0, 0, 0], false),
        ([0, 0xFFFF, 0xFFFF, 0], false),
        ([0; 4], true),
    ] {
        let s = Setup {
            en,
            tint: [7, 33, 0, 90],
            conclk: true,
            tchk: true,
            delay_us: 60,
            serial_pins,
        };
        let at: Vec<u64> = (1..=160).map(|i| i * 7).collect();
        same_runs(s, &at, u32::MAX, 0x5555_5555).unwrap_or_else(|e| panic!("{e}"));
    }
}
