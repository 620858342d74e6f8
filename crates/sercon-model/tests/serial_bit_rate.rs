//! Bit rate of the serial interface from pins and bits: every row of the SERCON816 table
//! (816 §2.3.1) and the SERCON410B's SBAUD / SWBAUD / ENTSBAUD / SREGEN (410B §2, §4.1 1H;
//! ERRATA 1H.6, 1H.10, 1H.15).

use sercon_model::config::Straps;
use sercon_model::serial_settings::{
    BitClock, DividedClock, SerialSettingsError, bit_clock, is_410b_compatible_mode,
};
use sercon_regs::Variant;
use sercos_wire::time::{BitRate, Duration};

const SCLK_64MHZ: u64 = 64_000_000;
const SWBAUD: u16 = 1 << 6;
const ENTSBAUD: u16 = 1 << 10;
const SWBAUD16: u16 = 1 << 15;

fn straps(sbaud: bool, sbaud16: bool) -> Straps {
    Straps {
        sbaud,
        sbaud16,
        tm0: true,
        tm1: true,
    }
}

/// Register 1H with the three rate bits; `None` is the table's "X" (tested with both values).
fn reg1(entsbaud: bool, swbaud: bool, swbaud16: bool) -> u16 {
    (if entsbaud { ENTSBAUD } else { 0 })
        | (if swbaud { SWBAUD } else { 0 })
        | (if swbaud16 { SWBAUD16 } else { 0 })
}

/// One row of 816 table 2.3.1: ENTSBAUD, SBAUD pin, SBAUD16 pin, SWBAUD, SWBAUD16 (None = x/X),
/// bit rate at SCLK = 64 MHz.
type Row = (bool, Option<bool>, bool, Option<bool>, Option<bool>, u32);

// 816 §2.3.1, table "Bit rate for SCLK = 64 MHz", all ten rows in order.
const TABLE_2_3_1: [Row; 10] = [
    (false, Some(true), true, None, None, 2),
    (false, Some(false), true, None, None, 4),
    (true, None, true, Some(true), None, 2),
    (true, None, true, Some(false), None, 4),
    (false, Some(true), false, None, None, 8),
    (false, Some(false), false, None, None, 16),
    (true, None, false, Some(true), Some(true), 2),
    (true, None, false, Some(false), Some(true), 4),
    (true, None, false, Some(true), Some(false), 8),
    (true, None, false, Some(false), Some(false), 16),
];

fn expand(v: Option<bool>) -> Vec<bool> {
    match v {
        Some(b) => vec![b],
        None => vec![false, true],
    }
}

#[test]
fn sercon816_every_row_of_table_2_3_1() {
    // 816 §2.3.1: every row, with every "don't care" cell tried at both values.
    for (i, &(ent, sbaud, sbaud16, swbaud, swbaud16, mbit)) in TABLE_2_3_1.iter().enumerate() {
        let want = BitRate::from_mbit(mbit).expect("table rates are SERCOS rates");
        for sb in expand(sbaud) {
            for sw in expand(swbaud) {
                for sw16 in expand(swbaud16) {
                    let clk = bit_clock(
                        Variant::Sercon816,
                        &straps(sb, sbaud16),
                        SCLK_64MHZ,
                        reg1(ent, sw, sw16),
                    );
                    assert_eq!(
                        clk.bit_rate(),
                        Ok(want),
                        "row {} (SBAUD={sb} SWBAUD={sw} SWBAUD16={sw16})",
                        i + 1
                    );
                    assert_eq!(clk.bit_time(), Ok(want.bit_time()), "row {}", i + 1);
                }
            }
        }
    }
}

#[test]
fn sercon816_bit_time_at_16_mbit_is_exactly_62_5_ns() {
    // 816 §2.3.1 row 6: SBAUD = 0, SBAUD16 = 0 → 16 Mbit/s; one bit is 62.5 ns = 62 500 ps.
    let clk = bit_clock(Variant::Sercon816, &straps(false, false), SCLK_64MHZ, 0);
    assert_eq!(clk.bit_time(), Ok(Duration::from_picos(62_500)));
    assert_eq!(
        clk,
        BitClock::Internal(DividedClock {
            source_hz: SCLK_64MHZ,
            divisor: 4
        })
    );
}

#[test]
fn sercon816_other_sclk_scales_the_rate() {
    // 816 §2.3.1: the DPLL runs at 4 × SCLK and 16 × the bit rate, so rate = SCLK / 4 at the
    // 16 Mbit/s setting; 48 MHz gives 12 Mbit/s, exact, but no SERCOS rate.
    let clk = bit_clock(Variant::Sercon816, &straps(false, false), 48_000_000, 0);
    let BitClock::Internal(c) = clk else {
        panic!("816 has no external clock")
    };
    assert_eq!(c.hz_exact(), Some(12_000_000));
    // 4 / 48 MHz = 83 333.3 ps: not representable, so an error rather than a rounded value.
    assert_eq!(
        clk.bit_time(),
        Err(SerialSettingsError::NotWholePicoseconds {
            source_hz: 48_000_000,
            divisor: 4
        })
    );
    assert!(matches!(
        clk.bit_rate(),
        Err(SerialSettingsError::NonStandardRate { .. })
    ));
}

#[test]
fn sercon410b_sbaud_pin_selects_rate_when_entsbaud_is_0() {
    // 410B §2 SBAUD: f_SCLK/16 when SBAUD = 0, f_SCLK/32 when SBAUD = 1; ERRATA 1H.10:
    // ENTSBAUD = 0 (reset) takes the pin. SWBAUD is then ignored (ERRATA 1H.6).
    for sw in [false, true] {
        let fast = bit_clock(
            Variant::Sercon410b,
            &straps(false, true),
            SCLK_64MHZ,
            reg1(false, sw, false),
        );
        let slow = bit_clock(
            Variant::Sercon410b,
            &straps(true, true),
            SCLK_64MHZ,
            reg1(false, sw, false),
        );
        assert_eq!(fast.bit_rate(), Ok(BitRate::Mbit4));
        assert_eq!(slow.bit_rate(), Ok(BitRate::Mbit2));
    }
}

#[test]
fn sercon410b_swbaud_selects_rate_when_entsbaud_is_1() {
    // ERRATA 1H.6 / 1H.10: ENTSBAUD = 1 takes SWBAUD: 0 = f_SCLK/16, 1 = f_SCLK/32; pin ignored.
    for pin in [false, true] {
        let fast = bit_clock(
            Variant::Sercon410b,
            &straps(pin, true),
            SCLK_64MHZ,
            reg1(true, false, false),
        );
        let slow = bit_clock(
            Variant::Sercon410b,
            &straps(pin, true),
            SCLK_64MHZ,
            reg1(true, true, false),
        );
        assert_eq!(fast.bit_time(), Ok(Duration::from_nanos(250)));
        assert_eq!(slow.bit_time(), Ok(Duration::from_nanos(500)));
    }
}

#[test]
fn sercon410b_swbaud16_has_no_effect() {
    // ERRATA 1H.15: on the 410B bit 15 is not used; SWBAUD16 must not reach 8/16 Mbit/s.
    let clk = bit_clock(
        Variant::Sercon410b,
        &straps(false, true),
        SCLK_64MHZ,
        reg1(true, false, true),
    );
    assert_eq!(clk.bit_rate(), Ok(BitRate::Mbit4));
}

#[test]
fn sercon410b_rate_follows_sclk() {
    // 410B §2 SCLK: "the frequency is 16 or 32 times the baud rate": 32 MHz / 16 = 2 Mbit/s.
    let clk = bit_clock(Variant::Sercon410b, &straps(false, true), 32_000_000, 0);
    assert_eq!(clk.bit_rate(), Ok(BitRate::Mbit2));
}

#[test]
fn sercon410b_sregen_0_means_external_clock() {
    // 410B §2 SREGEN: 0 = regeneration off, RxC and TxC are clock inputs; no rate from SCLK.
    for r1 in [0, ENTSBAUD, ENTSBAUD | SWBAUD] {
        let clk = bit_clock(Variant::Sercon410b, &straps(false, false), SCLK_64MHZ, r1);
        assert_eq!(clk, BitClock::External);
        assert_eq!(clk.bit_time(), Err(SerialSettingsError::ExternalClock));
        assert_eq!(clk.bit_rate(), Err(SerialSettingsError::ExternalClock));
    }
}

#[test]
fn compatible_mode_follows_sbaud16() {
    // 816 §2.3.2: SBAUD16 (old SREGEN) = 1 forces the 410B compatible mode.
    assert!(is_410b_compatible_mode(
        Variant::Sercon816,
        &straps(false, true)
    ));
    assert!(!is_410b_compatible_mode(
        Variant::Sercon816,
        &straps(false, false)
    ));
    assert!(is_410b_compatible_mode(
        Variant::Sercon410b,
        &straps(false, false)
    ));
}

#[test]
fn zero_sclk_is_an_error_not_a_panic() {
    let clk = bit_clock(Variant::Sercon816, &straps(false, false), 0, 0);
    assert_eq!(clk.bit_time(), Err(SerialSettingsError::ZeroFrequency));
    assert!(clk.bit_rate().is_err());
}
