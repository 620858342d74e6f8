//! Fuzz target `chip_ram_line`: an arbitrary RAM image, register writes and arbitrary line
//! segments (bits with or without a possibly wrong hint, filler, dark, light, any bit time)
//! fed to a chip that is advanced in bounded steps must never panic or hang
//! (`crates/sercon-model`: "no panics from input"; 410B §4.2 every RAM walk is bounded).
//!
//! Input: byte 0 picks the variant, master/slave, tracing, implied filler, whether
//! forwarded copies are released and whether an advance that stops before the output bound
//! keeps it (`Chip::advance_before_output`, as a simulation running a slave ahead does;
//! debug builds check every kept bound against a fresh walk); every advance also checks the
//! promise for any line input (`Chip::next_output_for_any_input`) asked after the one before,
//! across the line inputs in between; then 512 bytes of RAM image
//! (256 words from word 0, the rest of the RAM filled by repeating them); then 4-byte
//! records `op, a, b, c`: op % 4 = 0 write register a := bc, 1 line segment (kind a % 4,
//! bit time from b, length from c, the following c bytes as bits / hint telegram),
//! 2 advance by (bc + 1) × 100 ns, 3 read RAM / registers. At most 256 records.
//!
//! Build: `cargo fuzz build --sanitizer none chip_ram_line`

#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use sercon_model::pins::PinSet;
use sercon_model::serial_port::{FrameHint, LineSegment, LineSignal, Shared};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::SerconBus;
use sercos_wire::line::BitVec;
use sercos_wire::time::Duration;

fuzz_target!(|data: &[u8]| {
    let Some((&h0, rest)) = data.split_first() else {
        return;
    };
    let mut chip = Chip::new(if h0 & 1 == 0 {
        ChipConfig::sercon816()
    } else {
        ChipConfig::sercon410b()
    });
    if h0 & 2 != 0 {
        chip.set_traced_pins(PinSet::ALL);
    }
    // The simulator's line shortcuts (implied filler, forwarded copies carried).
    chip.set_implied_filler(h0 & 8 != 0);
    chip.set_forward_output(h0 & 16 == 0);
    let (image, body) = rest.split_at(rest.len().min(512));
    // A running chip: 1 µs unit, cycles of 50 µs, telegrams on, master or slave.
    common::start_running(&mut chip, h0, &common::image_words(image));
    let mut out = Vec::new();
    let mut next_start = chip.now();
    let mut records = common::Records::new(body);
    // The promise for any line input (`Chip::next_output_for_any_input`), as last asked after
    // an advance: it holds across line inputs, not across bus accesses.
    let mut any_input: Option<sercos_wire::time::Instant> = None;
    while let Some([op, a, b, c]) = records.next_record() {
        if op % 4 == 0 || op % 4 == 3 {
            any_input = None;
        }
        match op % 4 {
            0 => chip.write_register(a, u16::from_be_bytes([b, c])),
            1 => {
                let payload = records.payload(usize::from(c));
                let n = payload.len();
                // Bit times from 10 ns to 2.56 µs; segments in order of their start.
                let bit_time = Duration::from_nanos(10 * (u64::from(b) + 1));
                let start = next_start.max(chip.now());
                let signal = match a % 4 {
                    0 => {
                        let mut bits = BitVec::with_capacity(n * 8);
                        for byte in payload {
                            for i in 0..8 {
                                bits.push(byte >> (7 - i) & 1 == 1);
                            }
                        }
                        LineSignal::Bits(Shared::new(bits))
                    }
                    1 => LineSignal::Filler,
                    2 => LineSignal::Dark,
                    _ => LineSignal::Light,
                };
                let hint = (a & 0x10 != 0 && !payload.is_empty()).then(|| {
                    Shared::new(FrameHint {
                        telegram: Shared::from(payload),
                        offset: u64::from(a >> 5),
                        coded: None,
                    })
                });
                let seg = LineSegment {
                    start,
                    bit_time,
                    signal,
                    level_before: a & 4 != 0,
                    hint,
                    distorted: a & 8 != 0,
                    then_filler: b & 1 == 1,
                };
                next_start = seg.end().unwrap_or(start);
                chip.line_input(seg);
            }
            2 => common::advance_record(&mut chip, h0, b, c, &mut any_input),
            _ => {
                let _ = chip.read_ram(u16::from_be_bytes([a, b]));
                let _ = chip.read_register(c);
                let _ = chip.dma_read_receive();
                chip.dma_write_transmit(u16::from(a));
            }
        }
    }
    // A bounded tail: one more millisecond.
    let end = chip.now().saturating_add(Duration::from_millis(1));
    chip.advance_to(end);
    chip.take_line_output(&mut out);
});
