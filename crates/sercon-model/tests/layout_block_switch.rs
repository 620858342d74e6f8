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

/// The fuzz targets' set-up and `chip_ram_line`'s advance record, as the fuzz target runs them.
#[path = "../../../fuzz/fuzz_targets/common/mod.rs"]
#[allow(dead_code)]
mod fuzz_common;

/// `chip_ram_line`'s run of `data` (its records 0, register write, and 2, advance; this input
/// has no others).
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
    fuzz_common::start_running(&mut chip, h0, &fuzz_common::image_words(image));
    let mut any_input = None;
    let mut records = fuzz_common::Records::new(body);
    while let Some([op, a, b, c]) = records.next_record() {
        match op % 4 {
            0 => {
                any_input = None;
                chip.write_register(a, u16::from_be_bytes([b, c]));
            }
            2 => fuzz_common::advance_record(&mut chip, h0, b, c, &mut any_input),
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
