//! Pin-related serial settings: SCLKO2/SCLKO4 (410B §2, 816 §2.3.1), REPON after reset
//! (816 §2.3.3), test modes (410B §2 TM0/TM1, §4.1 2H.7–9), TxD1–6 (2H.0–6), POLRXD/POLTXD
//! (1H.7, 1H.9), RXDNRZ (ERRATA 1H.12) and L_ERRN (2H.14–15).

use sercon_model::config::Straps;
use sercon_model::serial_settings::{
    LErrnMode, RxdCoding, TestMode, TestModeSource, TxdOutput, lerrn_mode, light_on_from_rxd,
    pin_test_mode, repon_reset, rxd_coding, sclk_outputs, test_mode, txd_level_for_light,
    txd_outputs,
};
use sercon_regs::Variant;

fn straps(sbaud16: bool, tm0: bool, tm1: bool) -> Straps {
    Straps {
        sbaud: false,
        sbaud16,
        tm0,
        tm1,
    }
}

#[test]
fn sclko_table_816() {
    // 816 §2.3.1, table "SCLKO2, SCLKO4 for SCLK = 64 MHz": SBAUD16 = 1 → 32 / 16 MHz,
    // SBAUD16 = 0 → 64 / 32 MHz.
    let rows = [
        (true, 32_000_000, 16_000_000),
        (false, 64_000_000, 32_000_000),
    ];
    for (sbaud16, o2, o4) in rows {
        let out = sclk_outputs(Variant::Sercon816, &straps(sbaud16, true, true), 64_000_000);
        assert_eq!(out.sclko2.hz_exact(), Some(o2), "SBAUD16={sbaud16}");
        assert_eq!(out.sclko4.hz_exact(), Some(o4), "SBAUD16={sbaud16}");
    }
}

#[test]
fn sclko_410b_is_sclk_by_2_and_4() {
    // 410B §2 SCLKO2: SCLK divided by 2; SCLKO4: SCLK divided by 4, whatever pin 28 says.
    for sregen in [false, true] {
        let out = sclk_outputs(Variant::Sercon410b, &straps(sregen, true, true), 40_000_000);
        assert_eq!(out.sclko2.hz_exact(), Some(20_000_000));
        assert_eq!(out.sclko4.hz_exact(), Some(10_000_000));
        assert_eq!(out.sclko4.period().map(|d| d.as_picos()), Ok(100_000));
    }
}

#[test]
fn repon_reset_table_816() {
    // 816 §2.3.3 table: TM0 TM1 → REPON after reset: 11 → 1, 00 → 0, 01 → 1, 10 → 1.
    let rows = [
        (true, true, true),
        (false, false, false),
        (false, true, true),
        (true, false, true),
    ];
    for (tm0, tm1, repon) in rows {
        assert_eq!(
            repon_reset(Variant::Sercon816, &straps(false, tm0, tm1)),
            repon,
            "TM0={tm0} TM1={tm1}"
        );
    }
}

#[test]
fn repon_reset_410b_is_1() {
    // 410B §4.1 1H.3 REPON: reset value 1 (repeater on), independent of TM0/TM1.
    for tm0 in [false, true] {
        for tm1 in [false, true] {
            assert!(repon_reset(Variant::Sercon410b, &straps(true, tm0, tm1)));
        }
    }
}

#[test]
fn pin_test_modes_816() {
    // 816 §2.3.3 table, column "Test mode": 11 none, 00 none, 01 continuous light,
    // 10 zero bit stream.
    let rows = [
        (true, true, TestMode::Normal),
        (false, false, TestMode::Normal),
        (false, true, TestMode::ContinuousLight),
        (true, false, TestMode::ZeroBitStream),
    ];
    for (tm0, tm1, want) in rows {
        assert_eq!(
            pin_test_mode(Variant::Sercon816, &straps(false, tm0, tm1)),
            want
        );
    }
}

#[test]
fn pin_test_modes_410b() {
    // 410B §2 TM0, TM1: TM0 = 0 → continuous signal light, TM1 = 0 → zero bit stream; both 0
    // read as continuous light (docs/spec-notes.md, "Serial interface settings").
    let rows = [
        (true, true, TestMode::Normal),
        (false, true, TestMode::ContinuousLight),
        (true, false, TestMode::ZeroBitStream),
        (false, false, TestMode::ContinuousLight),
    ];
    for (tm0, tm1, want) in rows {
        assert_eq!(
            pin_test_mode(Variant::Sercon410b, &straps(true, tm0, tm1)),
            want
        );
    }
}

#[test]
fn tmode_overrides_pins() {
    // 410B §4.1 2H.7–9 TMODE0–2: 0–3 pins, 4 and 6 continuous light, 5 zero bit stream,
    // 7 normal; 816 §2.3.3: the coding does not change.
    for variant in Variant::ALL {
        for (tm0, tm1) in [(true, true), (false, true), (true, false)] {
            let s = straps(true, tm0, tm1);
            for tmode in 0u16..8 {
                let (mode, source) = test_mode(variant, &s, tmode << 7);
                let want = match tmode {
                    0..=3 => (pin_test_mode(variant, &s), TestModeSource::Pins),
                    4 | 6 => (TestMode::ContinuousLight, TestModeSource::Register),
                    5 => (TestMode::ZeroBitStream, TestModeSource::Register),
                    _ => (TestMode::Normal, TestModeSource::Register),
                };
                assert_eq!((mode, source), want, "{variant:?} TMODE={tmode}");
            }
        }
    }
    // Other bits of 2H do not leak into TMODE.
    let (m, _) = test_mode(
        Variant::Sercon816,
        &straps(true, true, true),
        0xFC7F & !(0b111 << 7),
    );
    assert_eq!(m, TestMode::Normal);
}

#[test]
fn txd_enables_and_port_mode() {
    // 410B §4.1 2H.0–5 ENTXD1–6: 0 = high impedance, 1 = transmit data (reset: all 1).
    assert_eq!(txd_outputs(0x003F), [TxdOutput::TransmitData; 6]);
    assert_eq!(txd_outputs(0x0000), [TxdOutput::HighZ; 6]);
    let out = txd_outputs(0b10_0101);
    assert_eq!(
        out,
        [
            TxdOutput::TransmitData,
            TxdOutput::HighZ,
            TxdOutput::TransmitData,
            TxdOutput::HighZ,
            TxdOutput::HighZ,
            TxdOutput::TransmitData,
        ]
    );
    // 2H.6 TXDMODE = 1: TxD2–6 output ENTXD2–6 as a port; TxD1 stays transmit data / high-Z.
    let out = txd_outputs(0x0040 | 0b01_0011);
    assert_eq!(
        out,
        [
            TxdOutput::TransmitData,
            TxdOutput::Port(true),
            TxdOutput::Port(false),
            TxdOutput::Port(false),
            TxdOutput::Port(true),
            TxdOutput::Port(false),
        ]
    );
    assert_eq!(txd_outputs(0x0040)[0], TxdOutput::HighZ);
}

#[test]
fn polarity_of_rxd_and_txd() {
    // 410B §4.1 1H.7 POLRXD: 0 = "light on" when RxD = 0, 1 = when RxD = 1.
    assert!(light_on_from_rxd(0, false));
    assert!(!light_on_from_rxd(0, true));
    assert!(light_on_from_rxd(1 << 7, true));
    assert!(!light_on_from_rxd(1 << 7, false));
    // 1H.9 POLTXD: 0 = "light on" when TxD = 0, 1 = when TxD = 1.
    assert!(!txd_level_for_light(0, true));
    assert!(txd_level_for_light(0, false));
    assert!(txd_level_for_light(1 << 9, true));
    // POLRXD does not change TxD and vice versa.
    assert!(!txd_level_for_light(1 << 7, true));
    assert!(light_on_from_rxd(1 << 9, false));
}

#[test]
fn rxdnrz_reading() {
    // ERRATA 1H.12: 0 = NRZI (reset), 1 = NRZ.
    assert_eq!(rxd_coding(0), RxdCoding::Nrzi);
    assert_eq!(rxd_coding(1 << 12), RxdCoding::Nrz);
    assert_eq!(rxd_coding(!(1u16 << 12)), RxdCoding::Nrzi);
}

#[test]
fn lerrn_per_lmode() {
    // 410B §4.1 2H.14–15 LMODE: 0 FIBBR and RDIST, 1 RDIST, 2 FIBBR, 3 inactive; §2 L_ERRN is
    // active low.
    let modes = [
        LErrnMode::FibbrOrRdist,
        LErrnMode::Rdist,
        LErrnMode::Fibbr,
        LErrnMode::Inactive,
    ];
    for (lmode, mode) in modes.into_iter().enumerate() {
        assert_eq!(lerrn_mode((lmode as u16) << 14 | 0x3FFF), mode);
        for rdist in [false, true] {
            for fibbr in [false, true] {
                let active = match lmode {
                    0 => rdist || fibbr,
                    1 => rdist,
                    2 => fibbr,
                    _ => false,
                };
                assert_eq!(mode.is_active(rdist, fibbr), active);
                assert_eq!(
                    mode.pin_level(rdist, fibbr),
                    !active,
                    "L_ERRN is active low"
                );
            }
        }
    }
}
