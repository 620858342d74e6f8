//! The timing control's events at a cycle's first µs (TCNT = TCNTST): INT_TIMEn and CON_CLK
//! at TINTn, a DIV_CLK pulse with INT_DIVCLK at TDIVCLK (410B §4.1 0CH.5, 1AH–20H, 5H.9-13;
//! 816 §2.7). A cycle start applies them together (`CyclePlan::start`); debug builds compare
//! that with applying them one by one at every cycle start.

mod common;

use common::*;
use sercon_model::pins::{Pin, PinSet};
use sercon_regs::{Register, SerconBusExt};

const INT_TIME0: u16 = 1 << 9;
const INT_TIME1: u16 = 1 << 10;
const INT_TIME3: u16 = 1 << 12;
const INT_DIVCLK: u16 = 1 << 13;
const DIVCLKMODE: u16 = 1 << 9;

fn edges(chip: &mut sercon_model::Chip, pin: Pin) -> Vec<(u64, bool)> {
    drain(chip)
        .into_iter()
        .filter(|e| e.pin == pin)
        .map(|e| (e.at.as_picos() / 1_000_000, e.level))
        .collect()
}

/// TDIVCLK = TCNTST: a 1 µs DIV_CLK pulse at each cycle start, with INT_DIVCLK; in
/// DIVCLKMODE = 1 only in every NDIVCLK-th cycle, the first included.
#[test]
fn a_divclk_pulse_at_tcntst_starts_with_each_cycle() {
    for (tcntst, ndivclk, want_starts) in [
        (0u16, 1u16, vec![10u64, 60, 110]),
        (7, 1, vec![10, 53, 96]),
        (0, DIVCLKMODE | 2, vec![10, 110]),
    ] {
        let mut chip = chip816();
        chip.set_traced_pins(PinSet::of(&[Pin::DivClk]));
        chip.write(Register::Tscyc0, 50);
        chip.write(Register::Tcntst, tcntst);
        chip.write(Register::Tdivclk, tcntst);
        chip.write(Register::Ndivclk, ndivclk);
        chip.write(Register::Tcycstart, 10);
        chip.write(Register::Ctrl0C, (3 << 12) | CTRL0C_CYCSTART);
        chip.advance_to(us(9));
        assert_eq!(chip.read(Register::IntFlagsHi) & INT_DIVCLK, 0);
        chip.advance_to(us(10));
        assert_ne!(chip.read(Register::IntFlagsHi) & INT_DIVCLK, 0);
        chip.advance_to(us(200));
        let want: Vec<(u64, bool)> = want_starts
            .iter()
            .flat_map(|t| [(*t, true), (t + 1, false)])
            .collect();
        assert_eq!(
            edges(&mut chip, Pin::DivClk),
            want,
            "TCNTST {tcntst}, 20H {ndivclk:#x}"
        );
    }
}

/// TINT0 = TINT1 = TCNTST: both flags at the cycle start, and CON_CLK, set and reset at the
/// same µs, stays inactive (reset wins); TINT3 = TCNTST alone sets INT_TIME3 there.
#[test]
fn time_interrupts_at_tcntst_come_with_the_cycle_start() {
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
    chip.write(Register::Tscyc0, 40);
    chip.write(Register::Tcntst, 3);
    for r in [Register::Tint0, Register::Tint1, Register::Tint3] {
        chip.write(r, 3);
    }
    chip.write(Register::Tint2, 30);
    chip.write(
        Register::Ctrl0C,
        CTRL0C_ENCONCLK | (2 << 12) | CTRL0C_CYCSTART,
    );
    chip.advance_to(us(0));
    let hi = chip.read(Register::IntFlagsHi);
    assert_eq!(
        hi & (INT_TIME0 | INT_TIME1 | INT_TIME3),
        INT_TIME0 | INT_TIME1 | INT_TIME3
    );
    chip.advance_to(us(100));
    assert!(edges(&mut chip, Pin::ConClk).is_empty(), "reset wins");
    // TINT0 alone at TCNTST: CON_CLK goes active with the start.
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
    chip.write(Register::Tscyc0, 40);
    chip.write(Register::Tint0, 0);
    chip.write(Register::Tint1, 20);
    chip.write(Register::Tcycstart, 5);
    chip.write(
        Register::Ctrl0C,
        CTRL0C_ENCONCLK | (2 << 12) | CTRL0C_CYCSTART,
    );
    chip.advance_to(us(100));
    assert_eq!(
        edges(&mut chip, Pin::ConClk),
        vec![(5, true), (25, false), (45, true), (65, false)]
    );
}
