//! Fuzz target `quiet_events`: two chips get the same RAM image, register writes, line
//! segments and advances; on one, interrupt output INT0 always carries INT_RWAIT, INT_TEND
//! and INT_COMEND, so a receive window's opening, a transmit telegram's end and the end
//! marker are events of their own; the other applies them with its next event or bus access
//! (`crates/sercon-model`, spec-notes "Events nobody sees at once"). Whatever comes, both
//! must send the same line output and read the same status, flags, header registers and RAM
//! (410B §4.1 3H, 4H, 5H, 17H, 21H–26H; §4.2).
//!
//! Input as `chip_ram_line`: byte 0 (variant, master or slave, implied filler), 512 bytes of
//! RAM image, then 4-byte records `op, a, b, c`: op % 4 = 0 register write, 1 line segment
//! (hinted telegram bits, filler, dark or light), 2 advance, 3 compare what a host reads.
//!
//! Build: `cargo fuzz build --sanitizer none quiet_events`

#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use sercon_model::serial_port::{FrameHint, LineSegment, LineSignal, Shared};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::SerconBus;
use sercos_wire::line::{BitVec, Coding, Encoder, LineConfig, Polarity};
use sercos_wire::time::Duration;

/// 410B §4.1 3H.1 ENINT0; 4H.4 INT_COMEND, 4H.11 INT_TEND, 4H.12 INT_RWAIT.
const ENINT0: u16 = 1 << 1;
const QUIET_FLAGS: u16 = (1 << 4) | (1 << 11) | (1 << 12);
/// 410B §4.1 3H.6 COMACT, 3H.7 COMBLK, 3H.9 FLTMT, 3H.10 FLRWAIT, 3H.11 FLREC.
const STATUS_3H: u16 = (1 << 6) | (1 << 7) | (1 << 9) | (1 << 10) | (1 << 11);

/// The event chip keeps INT0 on the quiet flags whatever the input wrote.
fn keep_events(c: &mut Chip) {
    let c3 = c.read_register(0x03);
    c.write_register(0x03, c3 | ENINT0);
    let en = c.read_register(0x06);
    c.write_register(0x06, en | QUIET_FLAGS);
}

/// What a host reads that the quiet events change, and a digest of the RAM.
fn host_view(c: &mut Chip) -> ([u16; 10], u64) {
    let regs = [
        c.read_register(0x03) & STATUS_3H,
        c.read_register(0x04),
        c.read_register(0x05),
        c.read_register(0x17),
        c.read_register(0x21),
        c.read_register(0x22),
        c.read_register(0x23),
        c.read_register(0x24),
        c.read_register(0x25),
        c.read_register(0x26),
    ];
    let words = c.config().variant.ram_words();
    let digest = (0..words).fold(0u64, |h, a| {
        h.wrapping_mul(0x100_0000_01b3)
            .wrapping_add(u64::from(c.read_ram(a)))
    });
    (regs, digest)
}

fuzz_target!(|data: &[u8]| {
    let Some((&h0, rest)) = data.split_first() else {
        return;
    };
    let config = if h0 & 1 == 0 {
        ChipConfig::sercon816()
    } else {
        ChipConfig::sercon410b()
    };
    let mut chips = [Chip::new(config.clone()), Chip::new(config)];
    let (image, body) = rest.split_at(rest.len().min(512));
    let words = common::image_words(image);
    for chip in &mut chips {
        chip.set_implied_filler(h0 & 8 != 0);
        common::start_running(chip, h0, &words);
    }
    keep_events(&mut chips[0]);
    let mut next_start = chips[1].now();
    let mut outs = [Vec::new(), Vec::new()];
    let mut records = common::Records::new(body);
    while let Some([op, a, b, c]) = records.next_record() {
        match op % 4 {
            0 => {
                for chip in &mut chips {
                    chip.write_register(a, u16::from_be_bytes([b, c]));
                }
                keep_events(&mut chips[0]);
            }
            1 => {
                let payload = records.payload(usize::from(c).min(40));
                // 16 or 4 Mbit/s (the chips' own rates) or another.
                let bit_time = Duration::from_picos(match b % 3 {
                    0 => 62_500,
                    1 => 250_000,
                    _ => 1_000 * (u64::from(b) + 1),
                });
                let start = next_start.max(chips[1].now()).max(chips[0].now());
                let (signal, hint) = match a % 4 {
                    0 => {
                        let mut enc =
                            Encoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnLow));
                        let mut bits = BitVec::new();
                        if enc.encode(payload, &mut bits).is_err() {
                            continue;
                        }
                        let hint = Shared::new(FrameHint {
                            telegram: Shared::from(payload),
                            offset: 0,
                            coded: None,
                        });
                        (LineSignal::Bits(Shared::new(bits)), Some(hint))
                    }
                    1 => (LineSignal::Filler, None),
                    2 => (LineSignal::Dark, None),
                    _ => (LineSignal::Light, None),
                };
                let seg = LineSegment {
                    start,
                    bit_time,
                    signal,
                    level_before: false,
                    hint,
                    distorted: a & 8 != 0,
                    then_filler: b & 1 == 1,
                };
                next_start = seg.end().unwrap_or(start);
                for chip in &mut chips {
                    chip.line_input(seg.clone());
                }
            }
            2 => {
                let step = Duration::from_nanos(100 * (u64::from(u16::from_be_bytes([b, c])) + 1));
                let t = chips[1].now().saturating_add(step);
                for (chip, out) in chips.iter_mut().zip(&mut outs) {
                    chip.advance_to(t);
                    chip.take_line_output(out);
                }
                assert_eq!(outs[0], outs[1], "line output");
                for out in &mut outs {
                    out.clear();
                }
            }
            _ => {
                let [event, folded] = &mut chips;
                assert_eq!(host_view(event), host_view(folded), "host view");
            }
        }
    }
    let [event, folded] = &mut chips;
    assert_eq!(host_view(event), host_view(folded), "host view at the end");
});
