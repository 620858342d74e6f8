//! The SERCON816 watchdog through the bus (816 §2.6, §2.11.2 28H–2AH).

mod common;

use common::*;
use sercon_model::pins::{Pin, PinEvent, PinSet};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::{Register, SerconBusExt};
use sercos_wire::time::{Duration, Instant};

const WDOG_START: u16 = 1 << 0;
const INT_WDOG: u16 = 1 << 1;
const WDOUT_SET: u16 = 1 << 2;
const EN0_INT_WDOG: u16 = 1 << 3;
const WDOG_MSTEN: u16 = 1 << 5;
const ENTMT: u16 = 1 << 8;

fn chip_at(mclk_hz: u64, mclkdiv: u16) -> Chip {
    let mut cfg = ChipConfig::sercon816();
    cfg.mclk_hz = mclk_hz;
    let mut chip = Chip::new(cfg);
    chip.write(Register::MclkDiv, mclkdiv);
    chip
}

fn int_wdog(chip: &mut Chip) -> bool {
    chip.read(Register::WdogCtrl) & INT_WDOG != 0
}

#[test]
fn interval_is_mclkdiv_plus_1_times_twdog_over_fmclk() {
    // 816 §2.6.3: T_WDOG = (MCLKDIV + 1) · TWDOG / f_MCLK.
    for (mclk_hz, mclkdiv, twdog, expect_us) in [
        (32_000_000u64, 31u16, 1000u16, 1000u64),
        (20_000_000, 19, 250, 250),
        (32_000_000, 63, 300, 600),
        (40_000_000, 19, 5000, 2500),
        (16_000_000, 15, 65_535, 65_535),
    ] {
        let mut chip = chip_at(mclk_hz, mclkdiv);
        chip.advance_to(us(3));
        chip.write(Register::Twdog, twdog);
        chip.write(Register::WdogCtrl, WDOG_START | EN0_INT_WDOG);
        assert_eq!(chip.read(Register::WdogCtrl) & 1, 1, "WDOG_STAT");
        let expiry = us(3 + expect_us);
        assert_eq!(
            chip.next_deadline(),
            Some(expiry),
            "{mclk_hz} {mclkdiv} {twdog}"
        );
        chip.advance_to(Instant::from_picos(expiry.as_picos() - 1));
        assert!(!int_wdog(&mut chip));
        chip.advance_to(expiry);
        assert!(int_wdog(&mut chip), "{mclk_hz} {mclkdiv} {twdog}");
        // 816 §2.6: "If the watchdog activates, it switches off automatically."
        assert_eq!(chip.read(Register::WdogCtrl) & 1, 0);
    }
}

#[test]
fn only_42h_triggers_and_only_a_running_watchdog() {
    // 816 §2.6.4: "writing the value 42H to the control bits WDOG_TRIG (29H,7-0)".
    let mut chip = chip_at(32_000_000, 31);
    chip.write(Register::Twdog, 100);
    chip.write(Register::WdogTrig, 0x42);
    assert_eq!(
        chip.read(Register::WdogCtrl) & 1,
        0,
        "42H does not start it"
    );
    chip.write(Register::WdogCtrl, WDOG_START);
    chip.advance_to(us(60));
    chip.write(Register::WdogTrig, 0x42);
    chip.advance_to(us(120));
    for other in [0x00u16, 0x41, 0x43, 0xFF, 0x4200, 0x0024] {
        chip.write(Register::WdogTrig, other);
    }
    chip.advance_to(us(159));
    assert!(!int_wdog(&mut chip));
    chip.advance_to(us(160));
    assert!(int_wdog(&mut chip), "expired 100 µs after the last 42H");
    // Bits 15-8 are not used: 0142H still writes 42H to WDOG_TRIG.
    let mut chip = chip_at(32_000_000, 31);
    chip.write(Register::Twdog, 100);
    chip.write(Register::WdogCtrl, WDOG_START);
    chip.advance_to(us(50));
    chip.write(Register::WdogTrig, 0x0142);
    chip.advance_to(us(149));
    assert!(!int_wdog(&mut chip));
    chip.advance_to(us(150));
    assert!(int_wdog(&mut chip));
}

#[test]
fn wdog_start_again_does_not_reload() {
    // Reading (spec-notes "WDOG_START while running"): starting is not a trigger.
    let mut chip = chip_at(32_000_000, 31);
    chip.write(Register::Twdog, 100);
    chip.write(Register::WdogCtrl, WDOG_START);
    chip.advance_to(us(50));
    chip.write(Register::WdogCtrl, WDOG_START);
    chip.advance_to(us(100));
    assert!(int_wdog(&mut chip));
}

#[test]
fn mst_start_triggers_in_master_mode_with_wdog_msten() {
    // 816 §2.6.5: triggered "by the start signal for the MST's"; "goes active after a
    // certain time interval after start of the last MST"; master mode and WDOG_MSTEN only.
    let run = |ctrl0c: u16, wd: u16| {
        let mut chip = chip_at(32_000_000, 31);
        chip.write(Register::Twdog, 80);
        chip.write(Register::Tscyc0, 50);
        chip.write(Register::WdogCtrl, WDOG_START | wd);
        // NCYC = 3: MSTs start at 0, 50 and 100 µs.
        chip.write(Register::Ctrl0C, ctrl0c | (3 << 12) | CTRL0C_CYCSTART);
        let mut expiry = None;
        for t in 1..=400 {
            chip.advance_to(us(t));
            if expiry.is_none() && int_wdog(&mut chip) {
                expiry = Some(t);
            }
        }
        expiry
    };
    assert_eq!(run(CTRL0C_MASTER, WDOG_MSTEN), Some(180));
    assert_eq!(run(CTRL0C_MASTER, 0), Some(80), "WDOG_MSTEN = 0");
    assert_eq!(
        run(0, WDOG_MSTEN),
        Some(80),
        "no MST without MSTEN/MSTMASTER"
    );
}

#[test]
fn expiry_clears_entmt_and_phas0_and_locks_them_until_int_wdog_is_cleared() {
    // 816 §2.6.2: ENTMT := 0, PHAS0 := 0H; "can be programmed again by the bus interface
    // only after the status bit INT_WDOG is cleared".
    let mut chip = chip_at(32_000_000, 31);
    chip.write(Register::Ctrl3, ENTMT);
    chip.write(Register::Phas, 0x0304);
    chip.write(Register::Twdog, 10);
    chip.write(Register::WdogCtrl, WDOG_START);
    chip.advance_to(us(10));
    assert_eq!(chip.read(Register::Ctrl3) & ENTMT, 0);
    assert_eq!(chip.read(Register::Phas), 0x0300, "PHAS1 is untouched");
    chip.write(Register::Ctrl3, ENTMT);
    chip.write(Register::Phas, 0x0504);
    assert_eq!(chip.read(Register::Ctrl3) & ENTMT, 0, "ENTMT locked");
    assert_eq!(
        chip.read(Register::Phas),
        0x0500,
        "PHAS0 locked, PHAS1 writable"
    );
    chip.write(Register::WdogCtrl, INT_WDOG); // CLR_INT_WDOG
    assert!(!int_wdog(&mut chip));
    chip.write(Register::Ctrl3, ENTMT);
    chip.write(Register::Phas, 0x0504);
    assert_eq!(chip.read(Register::Ctrl3) & ENTMT, ENTMT);
    assert_eq!(chip.read(Register::Phas), 0x0504);
}

#[test]
fn int_wdog_drives_int0_when_enabled() {
    // 816 §2.11.2 28H.3 EN0_INT_WDOG: "INT_WDOG triggers INT0".
    let mut chip = chip_at(32_000_000, 31);
    chip.set_traced_pins(PinSet::of(&[Pin::Int0]));
    chip.write(Register::Ctrl3, 1 << 1); // ENINT0
    chip.write(Register::Twdog, 25);
    chip.write(Register::WdogCtrl, WDOG_START | EN0_INT_WDOG);
    chip.advance_to(us(100));
    assert_eq!(
        drain(&mut chip),
        vec![PinEvent {
            at: us(25),
            pin: Pin::Int0,
            level: true
        }]
    );
    chip.write(Register::WdogCtrl, INT_WDOG | EN0_INT_WDOG);
    assert!(!chip.pin_level(Pin::Int0));
}

#[test]
fn wdogn_is_active_for_two_to_three_predivider_periods_when_enabled() {
    // 816 §2.6.1: WDOGN "remains active for the next minimum 2, maximum 3 periods".
    // 375 ns = 12 MCLK periods: off the µs grid, on an MCLK edge (writes are sampled there).
    for (enable, start_ns) in [(true, 0u64), (true, 375), (false, 0)] {
        let mut chip = chip_at(32_000_000, 31);
        chip.set_traced_pins(PinSet::of(&[Pin::Wdogn]));
        chip.advance_to(ns(start_ns));
        chip.write(Register::Twdog, 20);
        let out = if enable { WDOUT_SET } else { 0 };
        chip.write(Register::WdogCtrl, WDOG_START | out);
        assert_eq!(chip.read(Register::WdogCtrl) & WDOUT_SET, out, "WDOUT_STAT");
        chip.advance_to(us(100));
        let ev = drain(&mut chip);
        if !enable {
            assert!(ev.is_empty());
            continue;
        }
        let expiry = ns(start_ns) + Duration::from_micros(20);
        assert_eq!(ev.len(), 2, "{ev:?}");
        assert_eq!((ev[0].at, ev[0].level), (expiry, false));
        assert!(ev[1].level);
        let width = ev[1].at - ev[0].at;
        assert!(
            width > Duration::from_micros(2) && width <= Duration::from_micros(3),
            "{width}"
        );
    }
}

/// A watchdog started within its interval of the end of representable time (`Instant::MAX`)
/// at the top MCLK the configuration accepts (1 THz, a tick per picosecond) expires past that
/// end: it never fires, and nothing panics on the way (816 §2.6.3; the saturated expiry
/// tick reads as none, `mclk::Due`).
#[test]
fn a_watchdog_expiring_past_the_end_of_time_never_fires() {
    let mut chip = chip_at(1_000_000_000_000, 63);
    chip.advance_to(Instant::from_picos(u64::MAX - 1000));
    chip.write(Register::Twdog, 65_535);
    chip.write(Register::WdogCtrl, WDOG_START | EN0_INT_WDOG);
    assert_eq!(chip.read(Register::WdogCtrl) & 1, 1, "WDOG_STAT");
    chip.advance_to(Instant::MAX);
    assert!(!int_wdog(&mut chip));
    assert_eq!(chip.read(Register::WdogCtrl) & 1, 1, "still running");
}
