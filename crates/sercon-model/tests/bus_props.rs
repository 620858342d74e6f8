//! Property test: any sequence of bus accesses (any register address 00H–3FH, any RAM
//! address, interleaved with `advance_to`) on either variant never panics and leaves the model
//! consistent:
//!
//! * a R/W bit reads back what was just written (410B §4.1: "All control registers can be
//!   written to and read (R/W)"), except where a documented rule overrides the write: a
//!   software reset (1H.1 SWRST), and the watchdog lock of ENTMT (3H.8) and PHAS0 (0AH.7-0)
//!   while INT_WDOG = 1 (816 §2.6.2);
//! * unused bits read 0 (410B §4.1: "If control registers are read with bits that are not
//!   used, these bits are set to 0");
//! * VERSION reads the circuit code (816 §2.11.1.1);
//! * a RAM word reads back what was just written (410B §1, 816 §2.5);
//! * a register read changes nothing but RFIFO (27H), and reads what
//!   `Chip::peek_register` showed before it, INTFL0 / INTFL1 (3H.0, 3H.3) what
//!   `Chip::interrupt_requests` shows (410B §4.1);
//! * time only moves forward, and `next_deadline` is never in the past.

use proptest::prelude::*;
use sercon_model::Chip;
use sercon_model::config::{ChipConfig, Straps};
use sercon_model::pins::PinSet;
use sercon_regs::{SerconBus, Variant, register_spec};
use sercos_wire::time::{Duration, Instant};

#[derive(Debug, Clone)]
enum Op {
    ReadReg(u8),
    WriteReg(u8, u16),
    ReadRam(u16),
    WriteRam(u16, u16),
    Advance(u64),
}

fn op() -> impl Strategy<Value = Op> {
    // Registers 00H–3FH are weighted towards the ones that exist (00H–2AH).
    let reg = prop_oneof![4 => 0u8..=0x2A, 1 => 0x2Bu8..=0x3F];
    prop_oneof![
        3 => reg.clone().prop_map(Op::ReadReg),
        6 => (reg, any::<u16>()).prop_map(|(a, v)| Op::WriteReg(a, v)),
        1 => any::<u16>().prop_map(Op::ReadRam),
        1 => (any::<u16>(), any::<u16>()).prop_map(|(a, v)| Op::WriteRam(a, v)),
        // Mostly short steps (µs), sometimes several cycles (ms).
        2 => prop_oneof![0u64..2_000_000, 0u64..20_000_000_000].prop_map(Op::Advance),
    ]
}

fn config() -> impl Strategy<Value = ChipConfig> {
    (
        prop::sample::select(Variant::ALL.to_vec()),
        prop::sample::select(vec![12_000_000u64, 16_000_000, 20_000_000, 32_000_000]),
        any::<[bool; 4]>(),
    )
        .prop_map(|(variant, mclk_hz, s)| ChipConfig {
            variant,
            mclk_hz,
            sclk_hz: 64_000_000,
            straps: Straps {
                sbaud: s[0],
                sbaud16: s[1],
                tm0: s[2],
                tm1: s[3],
            },
        })
}

/// Bits of a write to `address` that a documented rule may keep from reading back.
fn exempt_bits(variant: Variant, address: u8, value: u16, int_wdog: bool) -> u16 {
    match address {
        // 410B §4.1 1H.1 SWRST: writing 1 resets the chip, so 1H reads its reset value.
        0x01 if value & 0x0002 != 0 => 0xFFFF,
        // 816 §2.6.2: ENTMT and PHAS0 can be written only after INT_WDOG is cleared.
        0x03 if variant == Variant::Sercon816 && int_wdog => 1 << 8,
        0x0A if variant == Variant::Sercon816 && int_wdog => 0x00FF,
        _ => 0,
    }
}

fn check(cfg: ChipConfig, ops: &[Op], traced: bool) -> Result<(), TestCaseError> {
    let variant = cfg.variant;
    let mut chip = Chip::new(cfg);
    if traced {
        chip.set_traced_pins(PinSet::ALL);
    }
    let mut last = chip.now();
    for op in ops {
        match *op {
            Op::ReadReg(a) => {
                // 410B §4.1: a read changes nothing but RFIFO (27H), whose oldest word it
                // takes; `peek_register` gives the same word without the read.
                let peeked = chip.peek_register(a);
                let before = format!("{chip:?}");
                let v = chip.read_register(a);
                prop_assert_eq!(v, peeked, "{:02X}H read against peek", a);
                if !sercon_regs::register::read_has_effect(a) {
                    let after = format!("{chip:?}");
                    prop_assert!(after == before, "a read of {:02X}H changed the chip", a);
                }
                if a & 0x3F == 3 {
                    // 3H.0 INTFL0, 3H.3 INTFL1.
                    prop_assert_eq!(chip.interrupt_requests(), (v & 1 != 0, v & 8 != 0));
                }
                let spec = register_spec(variant, a);
                prop_assert_eq!(v & spec.unused(), 0, "unused bits of {:02X}H read 1", a);
                if a == 0 {
                    // 816 §2.11.1.1: VERSION.
                    prop_assert_eq!(v, variant.version());
                }
            }
            Op::WriteReg(a, v) => {
                let int_wdog = variant.has_watchdog() && chip.read_register(0x28) & 0x0002 != 0;
                chip.write_register(a, v);
                let spec = register_spec(variant, a);
                let mask = spec.rw & !exempt_bits(variant, a, v, int_wdog);
                let back = chip.read_register(a);
                prop_assert_eq!(
                    back & mask,
                    v & mask,
                    "{:02X}H: wrote {:04X}, read {:04X} (R/W mask {:04X})",
                    a,
                    v,
                    back,
                    mask
                );
            }
            Op::ReadRam(a) => {
                let _ = chip.read_ram(a);
            }
            Op::WriteRam(a, v) => {
                chip.write_ram(a, v);
                prop_assert_eq!(chip.read_ram(a), v, "RAM word {:04X}", a);
            }
            Op::Advance(ps) => {
                let t = chip.now() + Duration::from_picos(ps);
                chip.advance_to(t);
                prop_assert_eq!(chip.now(), t);
            }
        }
        prop_assert!(chip.now() >= last, "time went back");
        last = chip.now();
        if let Some(d) = chip.next_deadline() {
            prop_assert!(
                d >= chip.now(),
                "next deadline {} before now {}",
                d,
                chip.now()
            );
        }
    }
    // Draining after any sequence must not panic and gives events in time order.
    let mut events = Vec::new();
    chip.drain_pin_events(&mut events);
    prop_assert!(events.windows(2).all(|w| w[0].at <= w[1].at));
    prop_assert!(
        events
            .iter()
            .all(|e| e.at <= chip.now() && e.at >= Instant::ZERO)
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(256)))]

    #[test]
    fn any_bus_sequence_keeps_the_model_consistent(
        cfg in config(),
        ops in prop::collection::vec(op(), 0..120),
        traced in any::<bool>(),
    ) {
        check(cfg, &ops, traced)?;
    }
}
