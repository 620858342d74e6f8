//! Timing outputs through the bus: DIV_CLK in the 410B mode and in the 816's DIVCLKMODE
//! = 1, CON_CLK from TINT0 to TINT1, INT_TIME0-3, INT_DIVCLK (410B §4.1 0CH, 1AH–20H,
//! 5H; 816 §2.7).

mod common;

use common::*;
use sercon_model::Chip;
use sercon_model::pins::{Pin, PinEvent, PinSet};
use sercon_regs::{Register, SerconBusExt};

const INT_DIVCLK: u16 = 1 << 13;
const POLDIVCLK: u16 = 1 << 8;
const DIVCLKMODE: u16 = 1 << 9;

fn edges(chip: &mut Chip, pin: Pin) -> Vec<(u64, bool)> {
    drain(chip)
        .into_iter()
        .filter(|e| e.pin == pin)
        .map(|e| (e.at.as_picos() / 1_000_000, e.level))
        .collect()
}

fn divclk_chip(ndivclk_reg: u16, tdivclk: u16, dt: u16, tscyc: u16) -> Chip {
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::DivClk]));
    chip.write(Register::Tscyc0, tscyc);
    chip.write(Register::Tdivclk, tdivclk);
    chip.write(Register::Dtdivclk, dt);
    chip.write(Register::Ndivclk, ndivclk_reg);
    chip
}

#[test]
fn divclk_410b_mode_gives_ndivclk_pulses_from_tdivclk_every_dtdivclk() {
    // 410B §4.1 1EH TDIVCLK "first pulse", 1FH DTDIVCLK "pulse distance", 20H NDIVCLK
    // "Number of DIV_CLK pulses within one communication cycle"; 1 µs wide.
    let mut chip = divclk_chip(3, 5, 20, 100);
    chip.write(Register::Ctrl0C, (2 << 12) | CTRL0C_CYCSTART);
    chip.advance_to(us(300));
    let want: Vec<(u64, bool)> = [5u64, 25, 45, 105, 125, 145]
        .iter()
        .flat_map(|t| [(*t, true), (t + 1, false)])
        .collect();
    assert_eq!(edges(&mut chip, Pin::DivClk), want);
    assert_ne!(chip.read(Register::IntFlagsHi) & INT_DIVCLK, 0);
}

#[test]
fn divclk_polarity_and_pulses_beyond_the_cycle() {
    // 410B §4.1 20H.8 POLDIVCLK = 1: 0-active. Pulses after TSCYC do not occur, and a
    // pulse in the last µs ends with the cycle (spec-notes "DIV_CLK").
    let mut chip = divclk_chip(POLDIVCLK | 5, 10, 15, 50);
    assert!(chip.pin_level(Pin::DivClk), "inactive high");
    drain(&mut chip);
    chip.write(Register::Ctrl0C, (1 << 12) | CTRL0C_CYCSTART);
    chip.advance_to(us(200));
    // Pulses at 10, 25, 40; 55 and 70 lie beyond the 50 µs cycle.
    assert_eq!(
        edges(&mut chip, Pin::DivClk),
        vec![
            (10, false),
            (11, true),
            (25, false),
            (26, true),
            (40, false),
            (41, true)
        ]
    );
}

#[test]
fn divclk_back_to_back_pulses_merge() {
    // DTDIVCLK = 1: each pulse starts as the previous ends; no zero-width glitch.
    let mut chip = divclk_chip(3, 10, 1, 50);
    chip.write(Register::Ctrl0C, (1 << 12) | CTRL0C_CYCSTART);
    chip.advance_to(us(60));
    assert_eq!(edges(&mut chip, Pin::DivClk), vec![(10, true), (13, false)]);
}

#[test]
fn divclkmode_1_pulses_once_every_ndivclk_cycles_from_the_first() {
    // 816 §2.7: "Active after each N-th cycle"; "goes active the first time in the first
    // SERCOS cycle"; pulse at TDIVCLK, polarity and length unchanged.
    let mut chip = divclk_chip(DIVCLKMODE | 3, 7, 2, 20);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.advance_to(us(200));
    let want: Vec<(u64, bool)> = [7u64, 67, 127, 187]
        .iter()
        .flat_map(|t| [(*t, true), (t + 1, false)])
        .collect();
    assert_eq!(edges(&mut chip, Pin::DivClk), want);
}

#[test]
fn divclkmode_1_programmed_mid_run_pulses_in_the_next_cycle() {
    // 816 §2.7: "or after the first cycle when NDIVCLK is being programmed to a value not
    // equal zero".
    let mut chip = divclk_chip(DIVCLKMODE, 7, 0, 20);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.advance_to(us(50));
    assert!(
        edges(&mut chip, Pin::DivClk).is_empty(),
        "NDIVCLK = 0: never"
    );
    chip.write(Register::Ndivclk, DIVCLKMODE | 2);
    chip.advance_to(us(150));
    assert_eq!(
        edges(&mut chip, Pin::DivClk),
        vec![
            (67, true),
            (68, false),
            (107, true),
            (108, false),
            (147, true),
            (148, false)
        ]
    );
}

#[test]
fn divclkmode_1_with_an_untraced_deadline_reaches_the_pulse() {
    // next_deadline names the traced pulse even many cycles ahead.
    let mut chip = divclk_chip(DIVCLKMODE | 50, 3, 0, 10);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    assert_eq!(chip.next_deadline(), Some(us(3)));
    chip.advance_to(us(3));
    assert_eq!(chip.next_deadline(), Some(us(4)));
    chip.advance_to(us(4));
    assert_eq!(chip.next_deadline(), Some(us(503)));
}

#[test]
fn conclk_is_active_from_tint0_to_tint1_under_each_polarity() {
    // 410B §4.1 0CH.5 ENCONCLK "active from TINT0 to TINT1", 0CH.6 POLCONCLK, 0CH.4 reads
    // the pin; 1AH/1BH "first/second edge of CON_CLK".
    for pol in [false, true] {
        let mut chip = chip816();
        chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
        chip.write(Register::Tscyc0, 100);
        chip.write(Register::Tint0, 20);
        chip.write(Register::Tint1, 70);
        let p = if pol { CTRL0C_POLCONCLK } else { 0 };
        chip.write(Register::Ctrl0C, CTRL0C_ENCONCLK | p);
        assert_eq!(chip.pin_level(Pin::ConClk), pol);
        drain(&mut chip);
        chip.write(
            Register::Ctrl0C,
            CTRL0C_ENCONCLK | p | (2 << 12) | CTRL0C_CYCSTART,
        );
        chip.advance_to(us(50));
        assert_eq!(chip.read(Register::Ctrl0C) & (1 << 4) != 0, !pol, "0CH.4");
        chip.advance_to(us(300));
        assert_eq!(
            edges(&mut chip, Pin::ConClk),
            vec![(20, !pol), (70, pol), (120, !pol), (170, pol)],
            "POLCONCLK = {pol}"
        );
    }
}

#[test]
fn conclk_with_tint1_before_tint0_spans_the_cycle_boundary() {
    // Reading (spec-notes "CON_CLK"): set at TINT0, reset at TINT1, a flip-flop.
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
    chip.write(Register::Tscyc0, 100);
    chip.write(Register::Tint0, 80);
    chip.write(Register::Tint1, 10);
    chip.write(
        Register::Ctrl0C,
        CTRL0C_ENCONCLK | (2 << 12) | CTRL0C_CYCSTART,
    );
    chip.advance_to(us(300));
    assert_eq!(
        edges(&mut chip, Pin::ConClk),
        vec![(80, true), (110, false), (180, true)]
    );
}

#[test]
fn conclk_stays_inactive_without_enconclk() {
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
    chip.write(Register::Tscyc0, 100);
    chip.write(Register::Tint0, 20);
    chip.write(Register::Tint1, 70);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.advance_to(us(300));
    assert!(drain(&mut chip).is_empty());
}

#[test]
fn time_interrupts_fire_when_tcnt_reaches_tint() {
    // 410B §4.1 1AH–1DH, 5H.9-12 INT_TIME0-3.
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 100);
    for (reg, t) in [
        (Register::Tint0, 10u16),
        (Register::Tint1, 20),
        (Register::Tint2, 30),
        (Register::Tint3, 200), // beyond the cycle: never
    ] {
        chip.write(reg, t);
    }
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    let mut seen = Vec::new();
    for t in 0..=100 {
        chip.advance_to(us(t));
        let hi = chip.read(Register::IntFlagsHi) & 0x1E00;
        if hi != 0 {
            seen.push((t, hi >> 9));
            chip.write(Register::IntFlagsHi, hi);
        }
    }
    assert_eq!(seen, vec![(10, 1), (20, 2), (30, 4)]);
}

#[test]
fn tint_written_mid_cycle_takes_effect_in_that_cycle() {
    // Reading (spec-notes "timing registers written mid-cycle"): comparators.
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
    chip.write(Register::Tscyc0, 100);
    chip.write(Register::Tint0, 80);
    chip.write(
        Register::Ctrl0C,
        CTRL0C_ENCONCLK | (1 << 12) | CTRL0C_CYCSTART,
    );
    chip.advance_to(us(30));
    chip.write(Register::Tint0, 50);
    chip.advance_to(us(100));
    assert_eq!(
        drain(&mut chip),
        vec![PinEvent {
            at: us(50),
            pin: Pin::ConClk,
            level: true
        }]
    );
}
