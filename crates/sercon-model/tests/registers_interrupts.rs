//! Interrupt flags, enables and the INT0/INT1 outputs (410B §4.1 3H–9H, ERRATA
//! "410B 3H.1 ENINT0", "410B 3H.2/3H.5 POLINT0/1", "410B 4H/5H").

mod common;

use common::*;
use sercon_model::pins::{Pin, PinEvent, PinSet};
use sercon_regs::{Register, SerconBusExt};

const INT_TIME0: u16 = 1 << 9;
const INT_TIME1: u16 = 1 << 10;
const ENINT0: u16 = 1 << 1;
const POLINT0: u16 = 1 << 2;
const ENINT1: u16 = 1 << 4;
const POLINT1: u16 = 1 << 5;
const INTFL0: u16 = 1 << 0;
const INTFL1: u16 = 1 << 3;

/// A chip whose TINT0 (at 10 µs) and TINT1 (at 20 µs) fire once (NCYC = 1).
fn timed_chip(ctrl3: u16) -> sercon_model::Chip {
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::Int0, Pin::Int1]));
    chip.write(Register::Tscyc0, 100);
    chip.write(Register::Tint0, 10);
    chip.write(Register::Tint1, 20);
    chip.write(Register::En0IntHi, INT_TIME0);
    chip.write(Register::En1IntHi, INT_TIME1);
    chip.write(Register::Ctrl3, ctrl3);
    chip.write(Register::Ctrl0C, (1 << 12) | CTRL0C_CYCSTART);
    chip
}

#[test]
fn interrupt_pins_follow_flags_under_each_polarity() {
    // ERRATA: POLINTn = 0 → 1-active, POLINTn = 1 → 0-active; ENINTn = 1 → enabled.
    for (pol0, pol1) in [(false, false), (true, false), (false, true), (true, true)] {
        let ctrl3 =
            ENINT0 | ENINT1 | if pol0 { POLINT0 } else { 0 } | if pol1 { POLINT1 } else { 0 };
        let mut chip = timed_chip(ctrl3);
        let before = drain(&mut chip);
        // Writing the polarity moves the idle level at once (time 0).
        assert_eq!(chip.pin_level(Pin::Int0), pol0);
        assert_eq!(chip.pin_level(Pin::Int1), pol1);
        assert!(before.iter().all(|e| e.at == us(0)));
        chip.advance_to(us(50));
        let ev = drain(&mut chip);
        assert_eq!(
            ev,
            vec![
                PinEvent {
                    at: us(10),
                    pin: Pin::Int0,
                    level: !pol0
                },
                PinEvent {
                    at: us(20),
                    pin: Pin::Int1,
                    level: !pol1
                },
            ],
            "POLINT0={pol0} POLINT1={pol1}"
        );
    }
}

#[test]
fn intfl_shows_the_request_and_enint_gates_the_pin() {
    // Reading (spec-notes "INTFL"): INTFLn is the request, ENINTn only gates the pin.
    let mut chip = timed_chip(0);
    chip.advance_to(us(30));
    assert_eq!(
        chip.read(Register::Ctrl3) & (INTFL0 | INTFL1),
        INTFL0 | INTFL1
    );
    assert!(!chip.pin_level(Pin::Int0), "ENINT0 = 0 keeps INT0 inactive");
    assert!(drain(&mut chip).is_empty());
    chip.write(Register::Ctrl3, ENINT0);
    assert!(chip.pin_level(Pin::Int0));
    assert_eq!(
        drain(&mut chip),
        vec![PinEvent {
            at: us(30),
            pin: Pin::Int0,
            level: true
        }]
    );
}

#[test]
fn writing_1_clears_a_flag_and_0_leaves_it() {
    // ERRATA "410B 4H/5H": write 1 clears, write 0 leaves.
    let mut chip = timed_chip(ENINT0 | ENINT1);
    chip.advance_to(us(30));
    assert_eq!(
        chip.read(Register::IntFlagsHi) & (INT_TIME0 | INT_TIME1),
        INT_TIME0 | INT_TIME1
    );
    drain(&mut chip);
    chip.write(Register::IntFlagsHi, 0);
    assert_eq!(
        chip.read(Register::IntFlagsHi) & (INT_TIME0 | INT_TIME1),
        INT_TIME0 | INT_TIME1
    );
    chip.advance_to(us(31));
    chip.write(Register::IntFlagsHi, INT_TIME0);
    assert_eq!(
        chip.read(Register::IntFlagsHi) & (INT_TIME0 | INT_TIME1),
        INT_TIME1
    );
    assert!(!chip.pin_level(Pin::Int0) && chip.pin_level(Pin::Int1));
    assert_eq!(
        drain(&mut chip),
        vec![PinEvent {
            at: us(31),
            pin: Pin::Int0,
            level: false
        }]
    );
}

#[test]
fn enabling_a_set_flag_raises_the_pin_at_once() {
    // 410B §4.1 6H–9H: "Interrupt flag activates INTn".
    let mut chip = timed_chip(ENINT0);
    chip.write(Register::En0IntHi, 0);
    chip.advance_to(us(40));
    assert!(!chip.pin_level(Pin::Int0));
    chip.write(Register::En0IntHi, INT_TIME1);
    assert!(chip.pin_level(Pin::Int0));
}

#[test]
fn next_deadline_names_the_interrupt_edge() {
    let mut chip = timed_chip(ENINT0 | ENINT1);
    assert_eq!(chip.next_deadline(), Some(us(10)));
    chip.advance_to(us(10));
    assert_eq!(chip.next_deadline(), Some(us(20)));
    chip.advance_to(us(20));
    // Flags stay set: nothing observable remains.
    assert_eq!(chip.next_deadline(), None);
}
