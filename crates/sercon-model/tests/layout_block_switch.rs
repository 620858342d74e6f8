//! The layout proof (`telegram_processor::layout`) made for one block's header list does not
//! outlive a run of the other block (410B §4.1 0CH: the registers choose the block a cycle
//! runs). Found by fuzz target `chip_ram_line` (session 16; the input is
//! `tests/data/layout_block_switch.bin`, that target's format): a SERCON410B master whose
//! proof covered block 0 only ran block 1 after a write to 0CH (written through its alias
//! 4CH, 410B §4.1: A5-0 select the register); block 1's receive header, aborted at the next
//! block's start, made its service container (410B §4.2.4, its SCPTn near the RAM's end, so
//! wrapping to word 0) write COMPT0, a word block 0's proof had read. The kept proof then no
//! longer held (debug builds: "kept layout proof"). A proof for other blocks is dropped when
//! a block starts that it does not cover.

use sercon_model::{Chip, ChipConfig};
use sercon_regs::SerconBus;
use sercos_wire::time::Duration;

/// The fuzz target's set-up (`fuzz/fuzz_targets/common/mod.rs::start_running`) and its records
/// 0 (register write) and 2 (advance, asking the output bound first); this input has no
/// others.
fn replay(data: &[u8]) -> Chip {
    let (&h0, rest) = data.split_first().expect("a header byte");
    let mut chip = Chip::new(if h0 & 1 == 0 {
        ChipConfig::sercon816()
    } else {
        ChipConfig::sercon410b()
    });
    chip.set_implied_filler(h0 & 8 != 0);
    chip.set_forward_output(h0 & 16 == 0);
    let (image, body) = rest.split_at(rest.len().min(512));
    let words: Vec<u16> = image
        .chunks(2)
        .map(|p| u16::from_le_bytes([p[0], p.get(1).copied().unwrap_or(0)]))
        .collect();
    for a in 0..chip.config().variant.ram_words() {
        chip.write_ram(a, words[usize::from(a) % words.len()]);
    }
    chip.write_register(0x0E, if h0 & 1 == 0 { 31 } else { 19 });
    chip.write_register(0x0F, 50);
    chip.write_register(0x03, 1 << 8);
    chip.write_register(0x0C, if h0 & 4 != 0 { 0b11 | (1 << 10) } else { 1 });
    for r in body.chunks_exact(4) {
        let (op, a, b, c) = (r[0], r[1], r[2], r[3]);
        match op % 4 {
            0 => chip.write_register(a, u16::from_be_bytes([b, c])),
            2 => {
                let step = Duration::from_nanos(100 * (u64::from(u16::from_be_bytes([b, c])) + 1));
                let t = chip.now().saturating_add(step);
                let promise = match (chip.next_output_bound(), chip.next_line_output_at()) {
                    (Some(x), Some(y)) => Some(x.min(y)),
                    (x, y) => x.or(y),
                };
                if h0 & 32 != 0 && promise.is_some_and(|p| t < p) {
                    chip.advance_before_output(t);
                } else {
                    chip.advance_to(t);
                }
                let mut out = Vec::new();
                chip.take_line_output(&mut out);
                let _ = chip.next_output_for_any_input();
                let mut events = Vec::new();
                chip.drain_pin_events(&mut events);
                let mut frames = Vec::new();
                chip.take_rx_frames(&mut frames);
                let _ = chip.next_deadline();
                let _ = chip.next_event_at();
            }
            _ => unreachable!("the input has only register writes and advances"),
        }
    }
    chip
}

#[test]
fn a_proof_for_one_block_is_made_afresh_when_the_other_block_runs() {
    let data = include_bytes!("data/layout_block_switch.bin");
    let mut chip = replay(data);
    // Block 1's service container wrote COMPT0 (word 0) on the way.
    assert_ne!(
        chip.read_ram(0),
        u16::from_le_bytes([data[1], data[2]]),
        "the input no longer reaches the case"
    );
    // Debug builds check every kept proof against a fresh one (`Chip::layout_proof`); the
    // bound asked now rests on a proof of the RAM as it is.
    let _ = chip.next_output_bound();
}
