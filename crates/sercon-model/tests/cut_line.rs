//! A receive line cut on its bit grid by later segments (the RS-485 bus of 410B Fig. 4, where
//! another driver garbles a telegram in progress, and then another; spec-notes "RS-485 bus")
//! is received as the line it finally shows: the chip's receive log holds exactly the frames
//! a decoder finds in that line read in one go (410B §1 NRZI, HDLC framing), whatever the
//! chip had reported of the telegram or the bits that were cut, and however far it had run.

mod common;

use proptest::prelude::*;
use sercon_model::serial_port::{FrameHint, LineSegment, LineSignal, RxFrame, Shared};
use sercos_wire::line::{BitVec, Coding, Decoded, Decoder, Encoder, LineConfig, Polarity};
use sercos_wire::time::{Duration, Instant};

/// 16 Mbit/s (816 §2.3.1).
const BT: Duration = Duration::from_picos(62_500);

fn bitvec(bits: &[bool]) -> BitVec {
    let mut v = BitVec::new();
    for b in bits {
        v.push(*b);
    }
    v
}

/// `telegram` coded from a dark line at `start`, with its hint (what a sender hands over).
fn coded(start: Instant, telegram: &[u8]) -> Option<LineSegment> {
    let mut enc = Encoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnHigh));
    let mut bits = BitVec::new();
    enc.encode(telegram, &mut bits).ok()?;
    Some(LineSegment {
        hint: Some(Shared::new(FrameHint {
            telegram: Shared::from(telegram),
            offset: 0,
            coded: None,
        })),
        ..LineSegment::bits(start, BT, bits, false)
    })
}

/// The frames a decoder finds in `line` (light levels from a dark line at `start`).
fn frames_of(start: Instant, line: &[bool]) -> Vec<RxFrame> {
    let at = |pos: u64| start.saturating_add(BT.saturating_mul(pos));
    let mut dec = Decoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnHigh));
    let mut out = Vec::new();
    let v = bitvec(line);
    dec.push(v.bits(), |d| {
        out.push(match d {
            Decoded::Telegram(f) => RxFrame {
                start: at(f.start),
                end: at(f.end),
                bytes: f.bytes.to_vec(),
                fcs_ok: true,
            },
            Decoded::Error { error, received } => RxFrame {
                start: at(error.start()),
                end: at(match error {
                    sercos_wire::line::LineError::FcsMismatch { end, .. }
                    | sercos_wire::line::LineError::TooShort { end, .. }
                    | sercos_wire::line::LineError::NotWholeBytes { end, .. } => end,
                    sercos_wire::line::LineError::Abort { at, .. }
                    | sercos_wire::line::LineError::TooLong { at, .. } => at + 1,
                }),
                bytes: received.to_vec(),
                fcs_ok: false,
            },
        });
    });
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(256)))]

    // A telegram cut at bit `k2` by bits `b2`, those cut at their bit `k3` by bits `b3`
    // and a steady tail (the undriven bus); the chip run to a point before each cut.
    #[test]
    fn a_line_cut_twice_on_its_grid_is_received_as_it_finally_is(
        telegram in proptest::collection::vec(any::<u8>(), 1..12),
        k2 in any::<prop::sample::Index>(),
        b2 in proptest::collection::vec(any::<bool>(), 1..160),
        k3 in any::<prop::sample::Index>(),
        b3 in proptest::collection::vec(any::<bool>(), 1..160),
        runs in (0u64..1000, 0u64..1000),
    ) {
        let start = common::us(10);
        let a = coded(start, &telegram).expect("encodable");
        let LineSignal::Bits(abits) = &a.signal else { unreachable!() };
        let abits: Vec<bool> = abits.bits().iter().collect();
        let k2 = k2.index(abits.len());
        let k3 = k3.index(b2.len());
        let mut chip = common::chip816();
        chip.line_input(a.clone());
        let level = |bits: &[bool], k: usize, before: bool| {
            k.checked_sub(1).and_then(|i| bits.get(i).copied()).unwrap_or(before)
        };
        let c2 = start.saturating_add(BT.saturating_mul(k2 as u64));
        let l2 = level(&abits, k2, false);
        // Run somewhere between the telegram's start and the cut (a permille of the way).
        let part = |from: Instant, to: Instant, pm: u64| {
            from.saturating_add(Duration::from_picos(
                to.saturating_duration_since(from).as_picos() / 1000 * pm,
            ))
        };
        chip.advance_to(part(start, c2, runs.0));
        chip.line_input(LineSegment::bits(c2, BT, bitvec(&b2), l2));
        let c3 = c2.saturating_add(BT.saturating_mul(k3 as u64));
        let l3 = level(&b2, k3, l2);
        let mut tail = b3.clone();
        let last = *b3.last().unwrap_or(&l3);
        tail.extend(std::iter::repeat_n(last, 16));
        chip.advance_to(part(c2, c3, runs.1));
        chip.line_input(LineSegment::bits(c3, BT, bitvec(&tail), l3));
        let mut got = Vec::new();
        chip.take_rx_frames(&mut got);
        let mut line: Vec<bool> = abits[..k2].to_vec();
        line.extend_from_slice(&b2[..k3]);
        line.extend_from_slice(&tail);
        prop_assert_eq!(got, frames_of(start, &line));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(256)))]

    // A telegram cut off its bit grid (a repeater's own telegram cutting one it repeats,
    // 410B §1: the two come from different clocks): the bit the cut falls in counts whole
    // and the new bits follow on the grid, as the DPLL locked to the old bits samples them
    // (spec-notes "Repeater collisions"); the chip run to a point before the cut.
    #[test]
    fn a_line_cut_off_its_grid_is_received_with_the_new_bits_on_it(
        telegram in proptest::collection::vec(any::<u8>(), 1..12),
        k2 in any::<prop::sample::Index>(),
        frac in 1u64..62_500,
        b2 in proptest::collection::vec(any::<bool>(), 1..160),
        run in 0u64..1000,
    ) {
        let start = common::us(10);
        let a = coded(start, &telegram).expect("encodable");
        let LineSignal::Bits(abits) = &a.signal else { unreachable!() };
        let abits: Vec<bool> = abits.bits().iter().collect();
        // Inside bit k2 (0-based), not at its start.
        let k2 = k2.index(abits.len());
        let c2 = start
            .saturating_add(BT.saturating_mul(k2 as u64))
            .saturating_add(Duration::from_picos(frac));
        let level = abits.get(k2).copied().unwrap_or(false);
        let mut chip = common::chip816();
        chip.line_input(a.clone());
        chip.advance_to(start.saturating_add(Duration::from_picos(
            c2.saturating_duration_since(start).as_picos() / 1000 * run,
        )));
        let mut tail = b2.clone();
        let last = *b2.last().unwrap_or(&level);
        tail.extend(std::iter::repeat_n(last, 16));
        chip.line_input(LineSegment::bits(c2, BT, bitvec(&tail), level));
        let mut got = Vec::new();
        chip.take_rx_frames(&mut got);
        let mut line: Vec<bool> = abits[..=k2].to_vec();
        line.extend_from_slice(&tail);
        prop_assert_eq!(got, frames_of(start, &line));
    }
}
