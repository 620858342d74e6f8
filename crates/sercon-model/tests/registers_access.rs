//! Register semantics through the bus on both variants, table-driven over sercon-regs'
//! access table: reset values, write masks, unused bits, action bits, 816 registers on
//! the 410B, RAM size (410B §4.1, 816 §2.11, ERRATA).

mod common;

use common::*;
use sercon_model::{Chip, ChipConfig, Straps};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};

/// Straps that make every pin-derived status bit predictable: TM0 = TM1 = 1 (REPON
/// resets to 1 on the 816 too, 816 §2.3.3), SBAUD = SBAUD16 = 0.
fn config(variant: Variant) -> ChipConfig {
    let mut cfg = match variant {
        Variant::Sercon410b => ChipConfig::sercon410b(),
        Variant::Sercon816 => ChipConfig::sercon816(),
    };
    cfg.straps = Straps::NORMAL;
    cfg
}

/// The reset value the access table gives, with the pin-level bits of `config`: 2H.10-11
/// are TM0-1 (410B §4.1 2H).
fn expected_reset(register: Register, variant: Variant) -> u16 {
    let spec = register.spec(variant);
    match register {
        Register::Ctrl2 => spec.reset | 0x0C00,
        _ => spec.reset,
    }
}

#[test]
fn every_register_reads_its_reset_value_on_both_variants() {
    // 410B §4.1: "The reset values of the control registers are shown in bold".
    for variant in Variant::ALL {
        let mut chip = Chip::new(config(variant));
        for register in Register::ALL {
            assert_eq!(
                chip.read(register),
                expected_reset(register, variant),
                "{register:?} on {variant:?}"
            );
        }
    }
}

#[test]
fn registers_of_the_816_read_0_and_ignore_writes_on_the_410b() {
    // 816 §2.11.2: 28H–2AH are new in the SERCON816.
    let mut chip = Chip::new(config(Variant::Sercon410b));
    for register in [Register::WdogCtrl, Register::WdogTrig, Register::Twdog] {
        chip.write(register, 0xFFFF);
        assert_eq!(chip.read(register), 0, "{register:?}");
    }
    chip.advance_to(us(100));
    assert_eq!(chip.read(Register::WdogCtrl), 0, "no watchdog on the 410B");
    // 816 §2.11.1.2 / ERRATA "410B 1H.15": SWBAUD16 and MCLKDIV bit 5 do not exist.
    chip.write(Register::MclkDiv, 0xFFFF);
    assert_eq!(chip.read(Register::MclkDiv), 0x1F1F);
    chip.write(Register::Ndivclk, 0xFFFF);
    assert_eq!(
        chip.read(Register::Ndivclk),
        0x01FF,
        "no DIVCLKMODE on the 410B"
    );
}

#[test]
fn writes_store_exactly_the_rw_bits_and_unused_or_action_bits_read_0() {
    // 410B §4.1: read-only and unused bits "can be set to 0 or 1; they are not evaluated
    // internally"; "If control registers are read with bits that are not used, these bits
    // are set to 0".
    for variant in Variant::ALL {
        for register in Register::ALL {
            let spec = register.spec(variant);
            for pattern in [0xFFFFu16, 0x0000, 0xA5A5, 0x5A5A] {
                let mut chip = Chip::new(config(variant));
                // 1H.1 SWRST would reset the chip: it is tested on its own.
                let value = if register == Register::Ctrl1 {
                    pattern & !0x0002
                } else {
                    pattern
                };
                chip.write(register, value);
                let read = chip.read(register);
                assert_eq!(
                    read & spec.rw,
                    value & spec.rw,
                    "R/W bits of {register:?} on {variant:?} after {value:#06x}"
                );
                assert_eq!(
                    read & !spec.readable(),
                    0,
                    "unused/action bits of {register:?} on {variant:?} after {value:#06x}"
                );
            }
        }
    }
}

#[test]
fn read_only_status_bits_ignore_writes() {
    // 410B §4.1 0H VERSION is R; 3H.6 COMACT is R; ERRATA "0H VERSION".
    for (variant, version) in [(Variant::Sercon410b, 2), (Variant::Sercon816, 0x10)] {
        let mut chip = Chip::new(config(variant));
        chip.write(Register::Version, 0xFFFF);
        assert_eq!(chip.read(Register::Version), version);
        chip.write(Register::Ctrl3, 0xFFC9 & !0x0100);
        assert_eq!(
            chip.read(Register::Ctrl3) & 0x00C9,
            0,
            "INTFL/COMACT stay 0"
        );
    }
}

#[test]
fn pin_levels_show_in_1h_and_2h() {
    // 410B §4.1 1H.4 SREGEN (pin 28), 1H.11 SBAUD, 2H.10-11 TM0-1.
    let mut cfg = ChipConfig::sercon410b();
    cfg.straps = Straps {
        sbaud: true,
        sbaud16: true,
        tm0: true,
        tm1: false,
    };
    let mut chip = Chip::new(cfg);
    assert_eq!(chip.read(Register::Ctrl1) & 0x0810, 0x0810);
    assert_eq!(chip.read(Register::Ctrl2) & 0x0C00, 0x0400);
}

#[test]
fn repon_resets_from_tm0_tm1_on_the_816() {
    // 816 §2.3.3: TM0 = TM1 = 0 → REPON 0 after reset; any other combination → 1.
    for (tm0, tm1, repon) in [
        (false, false, 0),
        (true, false, 1),
        (false, true, 1),
        (true, true, 1),
    ] {
        let mut cfg = ChipConfig::sercon816();
        cfg.straps.tm0 = tm0;
        cfg.straps.tm1 = tm1;
        let mut chip = Chip::new(cfg);
        assert_eq!(
            (chip.read(Register::Ctrl1) >> 3) & 1,
            repon,
            "TM0={tm0} TM1={tm1}"
        );
    }
}

#[test]
fn ram_has_1024_or_2048_words_and_wraps_beyond() {
    // 410B §1: 1024 words; 816 §2.5: 2048 words; the address bits above are not decoded.
    for (variant, words) in [(Variant::Sercon410b, 1024u16), (Variant::Sercon816, 2048)] {
        let mut chip = Chip::new(config(variant));
        chip.write_ram(words - 1, 0xBEEF);
        chip.write_ram(5, 0x1234);
        assert_eq!(chip.read_ram(words - 1), 0xBEEF);
        assert_eq!(chip.read_ram(words + 5), 0x1234, "{variant:?} wraps");
        assert_eq!(chip.read_ram(u16::MAX), 0xBEEF);
    }
}

#[test]
fn register_addresses_above_the_map_read_0() {
    // 410B §2: only A6-1 are decoded; 2BH–3FH hold no register.
    let mut chip = chip816();
    for address in 0x2Bu8..=0x3F {
        chip.write_register(address, 0xFFFF);
        assert_eq!(chip.read_register(address), 0);
    }
    // 0x40 + 0x0F decodes as TSCYC0 (0FH).
    chip.write_register(0x4F, 1234);
    assert_eq!(chip.read(Register::Tscyc0), 1234);
}

#[test]
fn rdcnt_and_cycstart_read_back_0() {
    // 410B §4.1 0CH.10 CYCSTART, 0CH.11 RDCNT: W (action) bits.
    let mut chip = chip816();
    chip.write(Register::Ctrl0C, CTRL0C_CYCSTART | CTRL0C_RDCNT);
    assert_eq!(chip.read(Register::Ctrl0C) & 0x0C00, 0);
}
