//! Set-up shared by the chip fuzz targets.

use sercon_model::Chip;
use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

/// The RAM image of the input, repeated over the whole RAM, as 16-bit words.
pub fn image_words(image: &[u8]) -> Vec<u16> {
    image
        .chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c.get(1).copied().unwrap_or(0)]))
        .collect()
}

/// Loads `words` (repeated) into the RAM and starts the chip running: a 1 µs unit, cycles
/// of 50 µs, telegrams on (3H.8 ENTMT), master (cycle start at once) or slave by `h0` bit 2,
/// variant by bit 0 (410B §4.1 0EH, 0FH, 03H, 0CH).
pub fn start_running(chip: &mut Chip, h0: u8, words: &[u16]) {
    if !words.is_empty() {
        for a in 0..chip.config().variant.ram_words() {
            chip.write_ram(a, words[usize::from(a) % words.len()]);
        }
    }
    chip.write_register(0x0E, if h0 & 1 == 0 { 31 } else { 19 });
    chip.write_register(0x0F, 50);
    chip.write_register(0x03, 1 << 8);
    chip.write_register(0x0C, if h0 & 4 != 0 { 0b11 | (1 << 10) } else { 1 });
}

/// The input's 4-byte records `op, a, b, c` after the RAM image (at most 256), each of
/// which may take payload bytes right after it.
pub struct Records<'a> {
    body: &'a [u8],
    taken: usize,
}

impl<'a> Records<'a> {
    /// The records of `body`.
    pub fn new(body: &'a [u8]) -> Self {
        Records { body, taken: 0 }
    }

    /// The next record, `None` at the end of the input or after 256 records.
    pub fn next_record(&mut self) -> Option<[u8; 4]> {
        let [op, a, b, c, tail @ ..] = self.body else {
            return None;
        };
        self.taken += 1;
        if self.taken > 256 {
            return None;
        }
        self.body = tail;
        Some([*op, *a, *b, *c])
    }

    /// Up to `n` payload bytes after the last record.
    pub fn payload(&mut self, n: usize) -> &'a [u8] {
        let (payload, tail) = self.body.split_at(n.min(self.body.len()));
        self.body = tail;
        payload
    }
}

/// `chip_ram_line`'s advance record: by `(bc + 1) × 100 ns`, with `Chip::advance_before_output`
/// when `h0` bit 5 asks and the advance stops before the output bound; nothing released may
/// start before that bound, nor before the promise for any line input (`any_input`, asked
/// after the advance before, across the line inputs in between; set again here). The chip's
/// other outputs are taken and dropped. (Used by `chip_ram_line` and by sercon-model's
/// `layout_block_switch.rs`, which replays one of its inputs; not by `quiet_events`.)
#[allow(dead_code)]
pub fn advance_record(chip: &mut Chip, h0: u8, b: u8, c: u8, any_input: &mut Option<Instant>) {
    let step = Duration::from_nanos(100 * (u64::from(u16::from_be_bytes([b, c])) + 1));
    let t = chip.now().saturating_add(step);
    // The promise a simulation sleeps on: nothing released starts before it.
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
    for seg in &out {
        assert!(
            promise.is_some_and(|p| seg.start >= p),
            "output at {:?} before the promise {promise:?}",
            seg.start
        );
        assert!(
            any_input.is_none_or(|p| seg.start >= p),
            "output at {:?} before the promise for any input {any_input:?}",
            seg.start
        );
    }
    *any_input = chip.next_output_for_any_input();
    let mut events = Vec::new();
    chip.drain_pin_events(&mut events);
    let mut frames = Vec::new();
    chip.take_rx_frames(&mut frames);
    let _ = chip.next_deadline();
    let _ = chip.next_event_at();
}
