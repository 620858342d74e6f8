//! Set-up shared by the chip fuzz targets.

use sercon_model::Chip;
use sercon_regs::SerconBus;

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
