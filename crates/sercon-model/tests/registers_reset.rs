//! RSTN and SWRST, and RSTFL (410B §4.1 1H.0-1; 816 §2.6, §2.6.2).

mod common;

use common::*;
use sercon_model::pins::{Pin, PinSet};
use sercon_regs::{Register, SerconBus, SerconBusExt};

const RSTFL: u16 = 1 << 0;
const SWRST: u16 = 1 << 1;

#[test]
fn rstfl_is_set_by_each_reset_and_cleared_by_writing_0() {
    // 410B §4.1 1H.0 RSTFL: R/W, reset value 1 ("Reset has taken place").
    let mut chip = chip816();
    assert_eq!(chip.read(Register::Ctrl1) & RSTFL, RSTFL);
    let c1 = chip.read(Register::Ctrl1);
    chip.write(Register::Ctrl1, c1 & !RSTFL);
    assert_eq!(chip.read(Register::Ctrl1) & RSTFL, 0);
    chip.write(Register::Ctrl1, SWRST);
    assert_eq!(
        chip.read(Register::Ctrl1) & RSTFL,
        RSTFL,
        "SWRST sets RSTFL"
    );
    chip.write(Register::Ctrl1, 0);
    chip.set_rstn(false);
    chip.set_rstn(true);
    assert_eq!(chip.read(Register::Ctrl1) & RSTFL, RSTFL, "RSTN sets RSTFL");
}

#[test]
fn swrst_resets_registers_and_timing_but_keeps_the_ram() {
    let mut chip = chip816();
    chip.set_traced_pins(PinSet::of(&[Pin::ConClk]));
    chip.write_ram(100, 0xCAFE);
    chip.write(Register::Tscyc0, 50);
    chip.write(Register::Tint0, 5);
    chip.write(Register::Tint1, 40);
    chip.write(Register::Phas, 0x0203);
    chip.write(Register::Ctrl0C, CTRL0C_ENCONCLK | CTRL0C_CYCSTART);
    chip.advance_to(us(20));
    assert!(chip.pin_level(Pin::ConClk));
    drain(&mut chip);
    chip.write(Register::Ctrl1, SWRST);
    // Everything is back to reset values at once; the RAM is not.
    assert_eq!(chip.read(Register::Phas), 0xFFFF);
    assert_eq!(chip.read(Register::Tscyc0), 0);
    assert_eq!(chip.read(Register::MclkDiv), 19);
    assert_eq!(chip.read(Register::Ctrl3) & (1 << 6), 0, "COMACT = 0");
    assert_eq!(chip.read_ram(100), 0xCAFE);
    assert!(!chip.pin_level(Pin::ConClk));
    let ev = drain(&mut chip);
    assert_eq!(ev.len(), 1);
    assert_eq!((ev[0].at, ev[0].level), (us(20), false));
    // SWRST is a pulse: the chip accepts writes right after it.
    chip.write(Register::Tscyc0, 7);
    assert_eq!(chip.read(Register::Tscyc0), 7);
    chip.advance_to(us(200));
    assert!(drain(&mut chip).is_empty(), "no cycle runs after the reset");
}

#[test]
fn rstn_low_holds_the_chip_and_ignores_writes() {
    // Reading (spec-notes "SWRST vs RSTN"): RSTN low holds the chip in reset.
    let mut chip = chip816();
    chip.write_ram(3, 0x1111);
    chip.write(Register::Tscyc0, 50);
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART);
    chip.advance_to(us(10));
    chip.set_rstn(false);
    chip.write(Register::Tscyc0, 99);
    chip.write_ram(3, 0x2222);
    assert_eq!(chip.read(Register::Tscyc0), 0);
    assert_eq!(chip.read_ram(3), 0x1111);
    assert_eq!(chip.next_deadline(), None);
    chip.advance_to(us(100));
    assert_eq!(chip.read(Register::IntFlagsLo), 0, "nothing runs in reset");
    chip.set_rstn(true);
    chip.write(Register::Tscyc0, 99);
    assert_eq!(chip.read(Register::Tscyc0), 99);
    // MCLKDIV is back at 19: on the 32 MHz 816 one "µs" is 20 MCLK = 625 ns.
    assert_eq!(chip.read(Register::MclkDiv), 19);
}

#[test]
fn reset_clears_int_wdog_and_wins_over_the_watchdog_lock() {
    // 816 §2.6: INT_WDOG "remains set until it is cleared by a reset or writing to
    // CLR_INT_WDOG"; §2.6.2: reset "has higher priority than reset through INT_WDOG".
    let mut chip = chip816();
    chip.write(Register::Twdog, 10);
    chip.write(Register::WdogCtrl, 1);
    chip.advance_to(us(20));
    assert_eq!(chip.read(Register::WdogCtrl) & 0b10, 0b10);
    assert_eq!(chip.read(Register::Phas), 0xFF00);
    chip.write(Register::Ctrl1, SWRST);
    assert_eq!(chip.read(Register::WdogCtrl), 0);
    assert_eq!(chip.read(Register::Phas), 0xFFFF);
    chip.write(Register::Phas, 0x0104);
    assert_eq!(chip.read(Register::Phas), 0x0104, "no lock after the reset");
}
