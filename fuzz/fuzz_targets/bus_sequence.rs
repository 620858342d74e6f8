//! Fuzz target `bus_sequence`: any sequence of bus accesses and time steps on either chip
//! variant must not panic, and a R/W register bit must read back what was written (the same
//! rules as `crates/sercon-model/tests/bus_props.rs`).
//!
//! Input: byte 0 picks the variant and straps, byte 1 the MCLK; then 5-byte records
//! `op, a, b, c, d`: op % 5 = 0 read register a, 1 write register a := cd, 2 read RAM ab,
//! 3 write RAM ab := cd, 4 advance by bcd (24 bit, big endian) × 8 ns (at most 134 ms).
//!
//! Build: `cargo fuzz build --sanitizer none bus_sequence`

#![no_main]

use libfuzzer_sys::fuzz_target;
use sercon_model::Chip;
use sercon_model::config::{ChipConfig, Straps};
use sercon_model::pins::PinSet;
use sercon_regs::{SerconBus, Variant, register_spec};
use sercos_wire::time::Duration;

fuzz_target!(|data: &[u8]| {
    let (head, body) = data.split_at(data.len().min(2));
    let h0 = head.first().copied().unwrap_or(0);
    let h1 = head.get(1).copied().unwrap_or(0);
    let variant = if h0 & 1 == 0 {
        Variant::Sercon816
    } else {
        Variant::Sercon410b
    };
    let cfg = ChipConfig {
        variant,
        mclk_hz: [12_000_000, 16_000_000, 20_000_000, 32_000_000][usize::from(h1 & 3)],
        sclk_hz: 64_000_000,
        straps: Straps {
            sbaud: h0 & 2 != 0,
            sbaud16: h0 & 4 != 0,
            tm0: h0 & 8 != 0,
            tm1: h0 & 16 != 0,
        },
    };
    let mut chip = Chip::new(cfg);
    if h0 & 32 != 0 {
        chip.set_traced_pins(PinSet::ALL);
    }
    let mut events = Vec::new();
    for rec in body.chunks_exact(5) {
        let &[op, a, b, c, d] = rec else { continue };
        let reg = a & 0x3F;
        let word = u16::from_be_bytes([c, d]);
        match op % 5 {
            0 => {
                let v = chip.read_register(reg);
                assert_eq!(v & register_spec(variant, reg).unused(), 0);
            }
            1 => {
                let int_wdog = variant.has_watchdog() && chip.read_register(0x28) & 2 != 0;
                chip.write_register(reg, word);
                let exempt = match reg {
                    0x01 if word & 2 != 0 => 0xFFFF, // 410B 1H.1 SWRST: reset
                    0x03 if int_wdog && variant == Variant::Sercon816 => 1 << 8, // 816 §2.6.2
                    0x0A if int_wdog && variant == Variant::Sercon816 => 0x00FF, // 816 §2.6.2
                    _ => 0,
                };
                let mask = register_spec(variant, reg).rw & !exempt;
                assert_eq!(chip.read_register(reg) & mask, word & mask);
            }
            2 => {
                let _ = chip.read_ram(u16::from_be_bytes([a, b]));
            }
            3 => {
                let addr = u16::from_be_bytes([a, b]);
                chip.write_ram(addr, word);
                assert_eq!(chip.read_ram(addr), word);
            }
            _ => {
                let _ = a;
                let steps = u64::from(u32::from_be_bytes([0, b, c, d]));
                let t = chip.now() + Duration::from_nanos(8 * steps);
                chip.advance_to(t);
                assert_eq!(chip.now(), t);
                events.clear();
                chip.drain_pin_events(&mut events);
            }
        }
        // The output bound after any access (debug builds check its remembered part
        // against a fresh walk: every bus access must drop it).
        let _ = chip.next_output_bound();
    }
});
