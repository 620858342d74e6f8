//! Communication-cycle timing through the bus: CYCSTART, CYC_CLK, TCYCSTART, NCYC,
//! TSCYC0/1, COMACT/COMBLK, INT_COMBLK0/1, INT_COMEND, TCNT/TCNTLT, MCLKST
//! (410B §4.1 3H, 4H, 0CH, 0EH, 0FH–14H).

mod common;

use common::*;
use sercon_model::Chip;
use sercon_model::pins::{Pin, PinSet};
use sercon_regs::{Register, SerconBusExt};

const COMACT: u16 = 1 << 6;
const COMBLK: u16 = 1 << 7;
const INT_COMBLK0: u16 = 1 << 2;
const INT_COMBLK1: u16 = 1 << 3;
const INT_COMEND: u16 = 1 << 4;
const INT_TIME0: u16 = 1 << 9;

fn comact(chip: &mut Chip) -> bool {
    chip.read(Register::Ctrl3) & COMACT != 0
}

fn tcntlt(chip: &mut Chip) -> u16 {
    let c = chip.read(Register::Ctrl0C);
    chip.write(Register::Ctrl0C, c | CTRL0C_RDCNT);
    chip.read(Register::Tcntlt)
}

/// Time of the next INT_TIME0 (polled µs by µs, clearing it).
fn tint0_times(chip: &mut Chip, until_us: u64) -> Vec<u64> {
    let mut v = Vec::new();
    for t in 0..=until_us {
        chip.advance_to(us(t));
        if chip.read(Register::IntFlagsHi) & INT_TIME0 != 0 {
            v.push(t);
            chip.write(Register::IntFlagsHi, INT_TIME0);
        }
    }
    v
}

#[test]
fn ncyc_cycles_of_tscyc0_follow_cycstart_after_tcycstart() {
    // 410B §4.1 0CH.10 CYCSTART "Trigger timing control after TCYCSTART", 0CH.12-15 NCYC,
    // 0FH TSCYC0, 14H TCYCSTART; 3H.6 COMACT.
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 40);
    chip.write(Register::Tcycstart, 15);
    chip.write(Register::Tint0, 0);
    chip.advance_to(us(5));
    chip.write(Register::Ctrl0C, (3 << 12) | CTRL0C_CYCSTART);
    chip.advance_to(us(19));
    assert!(!comact(&mut chip), "not before TCYCSTART");
    chip.advance_to(us(20));
    assert!(comact(&mut chip));
    let lo = chip.read(Register::IntFlagsLo);
    assert_eq!(lo & (INT_COMBLK0 | INT_COMBLK1 | INT_COMEND), INT_COMBLK0);
    chip.write(Register::IntFlagsLo, 0xFFFF);
    chip.write(Register::IntFlagsHi, 0xFFFF);
    // TINT0 = 0 fires at each cycle start: 20, 60, 100; nothing after 3 cycles.
    let starts: Vec<u64> = tint0_times(&mut chip, 300).into_iter().collect();
    assert_eq!(starts, vec![60, 100]);
    assert!(!comact(&mut chip));
    assert_ne!(chip.read(Register::IntFlagsLo) & INT_COMEND, 0);
}

#[test]
fn comend_fires_at_the_end_of_the_last_cycle() {
    // Reading (spec-notes "INT_COMEND").
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 30);
    chip.write(Register::Ctrl0C, (1 << 12) | CTRL0C_CYCSTART);
    chip.advance_to(us(29));
    assert_eq!(chip.read(Register::IntFlagsLo) & INT_COMEND, 0);
    assert!(comact(&mut chip));
    chip.advance_to(us(30));
    assert_ne!(chip.read(Register::IntFlagsLo) & INT_COMEND, 0);
    assert!(!comact(&mut chip));
}

#[test]
fn comblk0_selects_block_1_and_tscyc1() {
    // 410B §4.1 0CH.2 COMBLK0 = 1: "transmission block 1 is processed"; 10H TSCYC1;
    // 3H.7 COMBLK; 4H.3 INT_COMBLK1.
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 100);
    chip.write(Register::Tscyc1, 25);
    chip.write(Register::Tint0, 0);
    chip.write(Register::Ctrl0C, (1 << 2) | CTRL0C_CYCSTART);
    chip.advance_to(us(1));
    assert_eq!(
        chip.read(Register::Ctrl3) & (COMACT | COMBLK),
        COMACT | COMBLK
    );
    let lo = chip.read(Register::IntFlagsLo);
    assert_eq!(lo & (INT_COMBLK0 | INT_COMBLK1), INT_COMBLK1);
    chip.write(Register::IntFlagsHi, 0xFFFF);
    assert_eq!(tint0_times(&mut chip, 80), vec![25, 50, 75]);
}

#[test]
fn ncyc_0_runs_cycles_until_the_next_trigger() {
    // Reading (spec-notes "NCYC = 0"): continuous cycles.
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 50);
    chip.write(Register::Tint0, 0);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.write(Register::IntFlagsHi, 0xFFFF);
    assert_eq!(tint0_times(&mut chip, 520).len(), 10);
    assert!(comact(&mut chip));
}

#[test]
fn cyc_clk_triggers_on_the_edge_polcycclk_selects() {
    // 410B §4.1 0CH.8 ENCYCCLK, 0CH.9 POLCYCCLK: 0 = rising, 1 = falling edge; 0CH.7
    // reads the level.
    for falling in [false, true] {
        let mut chip = chip816();
        chip.write(Register::Tscyc0, 20);
        chip.write(Register::Tcycstart, 3);
        let pol = if falling { CTRL0C_POLCYCCLK } else { 0 };
        chip.write(Register::Ctrl0C, (1 << 12) | CTRL0C_ENCYCCLK | pol);
        chip.advance_to(us(10));
        chip.set_cyc_clk(true);
        assert_eq!(chip.read(Register::Ctrl0C) & (1 << 7), 1 << 7);
        chip.advance_to(us(20));
        chip.set_cyc_clk(false);
        chip.advance_to(us(24));
        let started_at = if falling { 23 } else { 13 };
        // One cycle (NCYC = 1) of 20 µs from the selected edge + TCYCSTART.
        let mut chip2 = chip.clone();
        chip2.advance_to(us(started_at + 19));
        assert!(comact(&mut chip2), "falling={falling}");
        chip.advance_to(us(started_at + 20));
        assert!(!comact(&mut chip), "falling={falling}");
        assert_ne!(chip.read(Register::IntFlagsLo) & INT_COMEND, 0);
    }
    // ENCYCCLK = 0: no trigger.
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 20);
    chip.set_cyc_clk(true);
    chip.advance_to(us(5));
    assert!(!comact(&mut chip));
}

#[test]
fn cycstart_is_ignored_by_a_sercos_slave() {
    // 410B §4.1 0CH.10: "(master)"; a slave's cycles start with the received MST.
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 20);
    chip.write(Register::Ctrl0C, 1 | CTRL0C_CYCSTART); // MSTEN, MSTMASTER = 0
    chip.advance_to(us(5));
    assert!(!comact(&mut chip));
}

#[test]
fn tcnt_counts_from_tcntst_and_rdcnt_latches_it() {
    // 410B §4.1 0CH.11 RDCNT "Load TCNT", 12H TCNTLT, 13H TCNTST "Initial value".
    let mut chip = chip816();
    assert_eq!(tcntlt(&mut chip), 0, "TCNT holds 0 before any cycle");
    chip.write(Register::Tscyc0, 500);
    chip.write(Register::Tcntst, 100);
    chip.advance_to(us(10));
    chip.write(Register::Ctrl0C, (1 << 12) | CTRL0C_CYCSTART);
    chip.advance_to(ns(47_500));
    assert_eq!(tcntlt(&mut chip), 137);
    assert_eq!(
        chip.read(Register::Tcntlt),
        137,
        "TCNTLT holds until the next RDCNT"
    );
    // The cycle ends when TCNT reaches TSCYC0: 400 µs after the start.
    chip.advance_to(us(409));
    assert!(comact(&mut chip));
    chip.advance_to(us(410));
    assert!(!comact(&mut chip));
    chip.advance_to(us(700));
    assert_eq!(tcntlt(&mut chip), 500, "TCNT stops at TSCYC0");
}

#[test]
fn tcntst_written_mid_cycle_applies_from_the_next_cycle() {
    // Reading (spec-notes "TCNTST written mid-cycle").
    let mut chip = chip816();
    chip.write(Register::Tscyc0, 100);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.advance_to(us(30));
    chip.write(Register::Tcntst, 50);
    assert_eq!(tcntlt(&mut chip), 30);
    chip.advance_to(us(110));
    assert_eq!(tcntlt(&mut chip), 60);
}

#[test]
fn mclkst_aligns_the_predivider_to_the_trigger() {
    // 410B §4.1 0EH MCLKST "Initial value for predivider" (spec-notes "MCLKST").
    // 816 at 32 MHz, MCLKDIV = 31: one µs = 32 MCLK. A trigger at 10.5 µs with
    // MCLKST = 0 gives µs ticks at 11.5, 12.5 …; with MCLKST = 16 at 11.0, 12.0 …
    for (mclkst, tint_at_ns) in [(0u16, 12_500u64), (16, 12_000), (31, 11_531)] {
        let mut chip = chip816();
        chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
        chip.write(Register::MclkDiv, (mclkst << 8) | 31);
        chip.write(Register::Tscyc0, 100);
        chip.write(Register::Tint0, 2);
        chip.advance_to(ns(10_500));
        chip.write(Register::Ctrl0C, CTRL0C_ENCONCLK | CTRL0C_CYCSTART);
        chip.advance_to(us(20));
        let ev = drain(&mut chip);
        assert_eq!(ev.len(), 1);
        // 31 MCLK periods after the trigger: 968.75 ns → 11 468.75 ns + 1 µs… compare
        // in picoseconds where the value is not whole nanoseconds.
        let want = match mclkst {
            31 => sercos_wire::time::Instant::from_picos(10_500_000 + 31_250 + 1_000_000),
            _ => ns(tint_at_ns),
        };
        assert_eq!(ev[0].at, want, "MCLKST = {mclkst}");
    }
}

#[test]
fn mclkdiv_sets_the_length_of_the_microsecond() {
    // 410B §4.1 0EH: MCLKDIV = f_MCLK / 1 MHz − 1; every timing register counts these.
    let mut chip = chip410(); // 20 MHz, MCLKDIV 19 after reset
    chip.write(Register::Tscyc0, 10);
    chip.write(Register::Tint0, 0);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.write(Register::IntFlagsHi, 0xFFFF);
    assert_eq!(tint0_times(&mut chip, 35), vec![10, 20, 30]);
    // The 410B's MCLKDIV has 5 bits: 39 is stored as 7 (8 MCLK = 0.4 µs per tick).
    let mut chip = chip410();
    chip.write(Register::MclkDiv, 39);
    assert_eq!(chip.read(Register::MclkDiv), 7);
    let mut chip = chip816(); // 32 MHz
    chip.write(Register::MclkDiv, 63); // 2 µs per tick
    chip.write(Register::Tscyc0, 10);
    chip.write(Register::Tint0, 0);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.write(Register::IntFlagsHi, 0xFFFF);
    assert_eq!(tint0_times(&mut chip, 65), vec![20, 40, 60]);
}
