//! Property tests: arbitrary RAM contents and arbitrary records through all three entry
//! points never panic, never loop, touch only the container's 256-word window (SCPTn plus
//! an 8-bit offset, 410B §4.2.4; regs reading of the buffer pointers) and change only the
//! service-channel bits of the record's first word (ERRATA "service info in a container").

use proptest::prelude::*;
use sercon_model::service_container::{ScMode, Variant, on_cycle, on_receive, on_transmit};

#[derive(Debug, Clone)]
enum Call {
    Transmit(Vec<u16>),
    Receive(Vec<u16>, bool),
    Cycle(u8, u8),
}

fn call() -> impl Strategy<Value = Call> {
    prop_oneof![
        prop::collection::vec(any::<u16>(), 0..7).prop_map(Call::Transmit),
        (prop::collection::vec(any::<u16>(), 0..7), any::<bool>())
            .prop_map(|(r, ok)| Call::Receive(r, ok)),
        (any::<u8>(), any::<u8>()).prop_map(|(h, b)| Call::Cycle(h, b)),
    ]
}

fn variant() -> impl Strategy<Value = Variant> {
    prop_oneof![Just(Variant::Sercon410b), Just(Variant::Sercon816)]
}

/// Whether `address` is within 256 words from `base`, wrapping in the RAM.
fn in_window(variant: Variant, base: u16, address: usize) -> bool {
    let words = usize::from(variant.ram_words());
    let offset = (address + words - usize::from(base)) % words;
    offset < 256
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(512)))]

    // 410B §4.2.4 (both tables); ERRATA "word addresses".
    #[test]
    fn arbitrary_ram_and_records_stay_inside(
        variant in variant(),
        seed in prop::collection::vec(any::<u16>(), 64),
        fill in any::<u16>(),
        // RAM slices of the variant's size or shorter (a truncated image must not panic).
        short in 0usize..3,
        nsv in any::<u8>(),
        master in any::<bool>(),
        calls in prop::collection::vec(call(), 1..40),
    ) {
        let words = usize::from(variant.ram_words());
        let len = match short { 0 => words, 1 => words / 2, _ => 7 };
        // Arbitrary contents: a repeated random pattern mixed with the address.
        let mut ram: Vec<u16> = (0..len)
            .map(|i| seed[i % seed.len()] ^ fill.rotate_left((i % 16) as u32))
            .collect();
        let mode = if master { ScMode::Master } else { ScMode::Slave };
        let scpt_word = 2 + usize::from(nsv & 7);
        for call in calls {
            let before = ram.clone();
            let base = ram.get(scpt_word).copied().unwrap_or(0) & variant.pointer_mask();
            match call {
                Call::Transmit(mut record) => {
                    let original = record.clone();
                    let out = on_transmit(&mut ram, variant, nsv, mode, &mut record);
                    prop_assert_eq!(record.len(), original.len());
                    let service_bits = if master { 0x003F } else { 0x0027 };
                    if let (Some(a), Some(b)) = (record.first(), original.first()) {
                        prop_assert_eq!(a & !service_bits, b & !service_bits);
                    }
                    prop_assert!(usize::from(out.info_words) < original.len().max(1));
                    prop_assert!(!out.rscend);
                }
                Call::Receive(record, ok) => {
                    let out = on_receive(&mut ram, variant, nsv, mode, &record, ok);
                    prop_assert_eq!(out.rscend, variant == Variant::Sercon816);
                    if !ok {
                        prop_assert!(out.raised.is_empty() && out.info_words == 0);
                    }
                    prop_assert!(usize::from(out.info_words) <= record.len().saturating_sub(1));
                }
                Call::Cycle(hs, busy) => {
                    let out = on_cycle(&mut ram, variant, nsv, mode, hs, busy);
                    if !master {
                        prop_assert_eq!(ram.clone(), before.clone());
                        prop_assert_eq!(out.ram_accesses, 0);
                    }
                }
            }
            prop_assert_eq!(ram.len(), len);
            for (i, (a, b)) in ram.iter().zip(before.iter()).enumerate() {
                if a != b {
                    prop_assert!(in_window(variant, base, i), "word {i:#x} outside SCPT {base:#x}");
                }
            }
        }
    }

    // 410B §4.2.4 HS_MDT / HS_AT: with any control words, a master that keeps getting its
    // own MHS back as AHS with BUSY 0 starts a step (toggles MHS) whenever M_BUSY is 0.
    #[test]
    fn master_toggles_mhs_only_when_acknowledged_and_not_m_busy(
        w in prop::collection::vec(any::<u16>(), 5),
        ahs_equal in any::<bool>(),
        busy in any::<bool>(),
    ) {
        let variant = Variant::Sercon410b;
        let mut ram = vec![0u16; 1024];
        ram[2] = 0x200;
        ram[0x200..0x205].copy_from_slice(&w);
        let hs_mdt = w[0] & 1 != 0;
        // Force HS_AT / BUSY_AT in word 1.
        let hs_at = if ahs_equal { hs_mdt } else { !hs_mdt };
        ram[0x201] = (ram[0x201] & !3) | u16::from(hs_at) | u16::from(busy) << 1;
        let m_busy = w[0] & 0x80 != 0;
        let mut record = [0u16; 2];
        let out = on_transmit(&mut ram, variant, 0, ScMode::Master, &mut record);
        let starts = ahs_equal && !busy && !m_busy;
        prop_assert_eq!(out.handshake, starts);
        prop_assert_eq!(record[0] & 1 != 0, hs_mdt ^ starts);
        prop_assert_eq!(ram[0x200] & 1 != 0, hs_mdt ^ starts);
    }
}
