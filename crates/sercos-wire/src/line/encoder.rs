//! Fast, table-driven encoder: telegram bytes → line bits.

use super::bits::{BitSink, SinkFull};
use super::config::LineConfig;
use super::error::EncodeError;
use super::fcs::fcs;
use super::nrzi::encode_word;
use super::{FLAG, FLAG_BITS, MAX_TELEGRAM_BYTES};

/// One entry of the zero-insertion table: the line bits of one byte (first bit most
/// significant, at most 8 data bits and 2 inserted 0s), their count, and the run of 1s after.
#[derive(Clone, Copy)]
struct Stuffed {
    bits: u16,
    n: u8,
    ones: u8,
}

/// ERRATA, Telegrams: bytes go least significant bit first and a 0 is inserted after five
/// consecutive 1s. Indexed by the run of 1s before the byte (0..=4: after five 1s the 0 is
/// inserted at once) and the byte.
static STUFF: [[Stuffed; 256]; 5] = build_stuff_table();

const fn build_stuff_table() -> [[Stuffed; 256]; 5] {
    let mut table = [[Stuffed {
        bits: 0,
        n: 0,
        ones: 0,
    }; 256]; 5];
    let mut start = 0;
    while start < 5 {
        let mut byte = 0;
        while byte < 256 {
            let mut bits: u16 = 0;
            let mut n: u8 = 0;
            let mut ones = start as u8;
            let mut i = 0;
            while i < 8 {
                let bit = (byte >> i) & 1;
                bits = (bits << 1) | bit as u16;
                n += 1;
                if bit == 1 {
                    ones += 1;
                    if ones == 5 {
                        // Zero insertion after the fifth consecutive 1.
                        bits <<= 1;
                        n += 1;
                        ones = 0;
                    }
                } else {
                    ones = 0;
                }
                i += 1;
            }
            table[start][byte] = Stuffed { bits, n, ones };
            byte += 1;
        }
        start += 1;
    }
    table
}

/// The stuffed bits of the FCS and telegram bytes, without flags.
fn stuffed_len(telegram: &[u8], fcs_bytes: [u8; 2]) -> u64 {
    let mut ones = 0usize;
    let mut total = 0u64;
    for &b in telegram.iter().chain(fcs_bytes.iter()) {
        let e = STUFF[ones][usize::from(b)];
        total += u64::from(e.n);
        ones = usize::from(e.ones);
    }
    total
}

/// Line bits of one telegram: both flags, ADR, data and FCS with the inserted 0s.
///
/// The same count [`Encoder::encode`] returns; with
/// [`frame_duration`](super::frame_duration) it gives the exact time the telegram
/// occupies the line.
pub fn frame_bit_len(telegram: &[u8]) -> u64 {
    2 * FLAG_BITS + stuffed_len(telegram, fcs(telegram).to_le_bytes())
}

/// Collects line-order data bits and hands them to the sink NRZI/NRZ-coded, 32 at a time.
struct WordWriter<'s, S: BitSink + ?Sized> {
    config: LineConfig,
    level: bool,
    acc: u64,
    n: u32,
    out: &'s mut S,
}

impl<S: BitSink + ?Sized> WordWriter<'_, S> {
    /// Appends `n` (≤ 32) data bits, first bit most significant.
    #[inline]
    fn push(&mut self, bits: u32, n: u32) -> Result<(), SinkFull> {
        self.acc = (self.acc << n) | u64::from(bits);
        self.n += n;
        if self.n >= 32 {
            self.n -= 32;
            let word = (self.acc >> self.n) as u32;
            let pins = encode_word(self.config, word, 32, &mut self.level);
            self.out.put(pins, 32)?;
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), SinkFull> {
        if self.n > 0 {
            let word = (self.acc as u32) & (u32::MAX >> (32 - self.n));
            let pins = encode_word(self.config, word, self.n, &mut self.level);
            self.out.put(pins, self.n)?;
            self.n = 0;
        }
        Ok(())
    }
}

/// Turns telegram bytes into line bits. Keeps the line level between telegrams, so a stream of
/// telegrams and idle filler written by one encoder is one continuous signal.
#[derive(Debug, Clone)]
pub struct Encoder {
    config: LineConfig,
    level: bool,
}

impl Encoder {
    /// An encoder whose line starts dark (`docs/spec-notes.md`, "Line coding").
    pub fn new(config: LineConfig) -> Self {
        Encoder {
            config,
            level: config.polarity.dark_level(),
        }
    }

    /// The configuration.
    pub fn config(&self) -> LineConfig {
        self.config
    }

    /// The pin level of the last bit written.
    pub fn level(&self) -> bool {
        self.level
    }

    /// Appends one frame (flag, ADR, data, FCS with 0s inserted, flag) for `telegram`
    /// (ADR and data) and returns its number of line bits, equal to [`frame_bit_len`].
    /// On error nothing is written and the level is unchanged.
    pub fn encode<S: BitSink + ?Sized>(
        &mut self,
        telegram: &[u8],
        out: &mut S,
    ) -> Result<u64, EncodeError> {
        if telegram.is_empty() {
            return Err(EncodeError::Empty);
        }
        if telegram.len() > MAX_TELEGRAM_BYTES {
            return Err(EncodeError::TooLong {
                len: telegram.len(),
                max: MAX_TELEGRAM_BYTES,
            });
        }
        let start = out.bit_len();
        let fcs_bytes = fcs(telegram).to_le_bytes();
        match self.write_frame(telegram, fcs_bytes, out) {
            Ok(level) => {
                self.level = level;
                Ok(out.bit_len() - start)
            }
            Err(e) => {
                out.truncate(start);
                Err(e.into())
            }
        }
    }

    fn write_frame<S: BitSink + ?Sized>(
        &self,
        telegram: &[u8],
        fcs_bytes: [u8; 2],
        out: &mut S,
    ) -> Result<bool, SinkFull> {
        let mut w = WordWriter {
            config: self.config,
            level: self.level,
            acc: 0,
            n: 0,
            out,
        };
        // ERRATA, Telegrams: BOF 7EH, not subject to zero insertion.
        w.push(u32::from(FLAG), 8)?;
        let mut ones = 0usize;
        for &b in telegram.iter().chain(fcs_bytes.iter()) {
            let e = STUFF[ones][usize::from(b)];
            w.push(u32::from(e.bits), u32::from(e.n))?;
            ones = usize::from(e.ones);
        }
        // ERRATA, Telegrams: EOF 7EH.
        w.push(u32::from(FLAG), 8)?;
        w.flush()?;
        Ok(w.level)
    }

    /// Appends `n` bits of idle filler: data 0s, which NRZI sends as a square wave that keeps
    /// the fibre toggling (sercos-facts, Line and framing; `docs/spec-notes.md`, "Line coding").
    /// On error nothing is written and the level is unchanged.
    pub fn idle<S: BitSink + ?Sized>(&mut self, n: u64, out: &mut S) -> Result<(), SinkFull> {
        let start = out.bit_len();
        let mut level = self.level;
        let mut left = n;
        while left > 0 {
            let k = left.min(32) as u32;
            let pins = encode_word(self.config, 0, k, &mut level);
            if let Err(e) = out.put(pins, k) {
                out.truncate(start);
                return Err(e);
            }
            left -= u64::from(k);
        }
        self.level = level;
        Ok(())
    }
}
