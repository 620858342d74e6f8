//! Arbitrary RAM contents and arbitrary received frames never panic or hang the telegram
//! processor (410B §4.2: every walk is bounded; errors go to PROGERR_FL). The frames come
//! over the line interface, encoded (with a hint) or corrupted (without one).

mod common;

use proptest::prelude::*;
use sercon_model::serial_port::{FrameHint, LineSegment, LineSignal, Shared};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::{Register, SerconBus, SerconBusExt};
use sercos_wire::line::{BitVec, Coding, Encoder, LineConfig, Polarity};
use sercos_wire::time::{Duration, Instant};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(48)))]

    #[test]
    fn arbitrary_ram_and_frames_never_panic(
        ram in proptest::collection::vec(any::<u16>(), 64),
        fill in any::<u16>(),
        master in any::<bool>(),
        frames in proptest::collection::vec(
            (0u64..300, 0u64..64, proptest::collection::vec(any::<u8>(), 0..40), any::<bool>()),
            0..12,
        ),
        reg25 in any::<u16>(),
    ) {
        let mut chip = common::arbitrary_chip(&ram, fill, master, Some(reg25));
        let mut frames = frames;
        frames.sort_by_key(|f| f.0);
        // 816 §2.3.1: 16 Mbit/s, 62.5 ns per bit.
        let bit_time = Duration::from_picos(62_500);
        for (start, flip, bytes, ok) in frames {
            let start = Instant::ZERO + Duration::from_micros(start);
            let mut enc = Encoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnLow));
            let mut bits = BitVec::new();
            if enc.encode(&bytes, &mut bits).is_err() {
                continue;
            }
            let (signal, hint) = if ok {
                let hint = Shared::new(FrameHint { telegram: Shared::from(&bytes[..]), offset: 0, coded: None });
                (bits, Some(hint))
            } else {
                // One light level inverted: the receiver decodes whatever that gives.
                let mut out = BitVec::with_capacity(bits.len() as usize);
                for (i, b) in bits.bits().iter().enumerate() {
                    out.push(b ^ (i as u64 == flip));
                }
                (out, None)
            };
            chip.line_input(LineSegment {
                start,
                bit_time,
                signal: LineSignal::Bits(Shared::new(signal)),
                level_before: false,
                hint,
                distorted: false,
                then_filler: false,
            });
        }
        // Bounded steps: a few hundred µs in 10 µs hops.
        for t in 1..=40u64 {
            chip.advance_to(Instant::ZERO + Duration::from_micros(10 * t));
            let _ = chip.next_deadline();
            let _ = chip.read(Register::Fifo);
        }
        let _ = chip.read(Register::ProgerrFl);
    }
}

/// Regression (fuzz target `chip_ram_line`, timeout): a 410B master whose RAM repeats
/// 717AH, 0000H must run 1 ms of cycles in bounded work.
#[test]
fn repeating_ram_pattern_runs_in_bounded_time() {
    let mut chip = Chip::new(ChipConfig::sercon410b());
    for a in 0..1024u16 {
        chip.write_ram(a, if a % 2 == 0 { 0x717A } else { 0 });
    }
    chip.write(Register::MclkDiv, 19);
    chip.write(Register::Tscyc0, 50);
    chip.write(Register::Ctrl3, 1 << 8);
    chip.write(Register::Ctrl0C, 0b11 | (1 << 10));
    for t in 1..=10u64 {
        chip.advance_to(Instant::ZERO + Duration::from_micros(100 * t));
    }
    // 410B §4.1 17H PROGERR_FL bit 1 (spec-notes): the header list loops.
    assert_ne!(chip.read(Register::ProgerrFl) & 0b10, 0);
}
