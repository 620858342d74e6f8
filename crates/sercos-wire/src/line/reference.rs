//! Plain bit-serial reference coder (with the `alloc` feature).
//!
//! One bit at a time, with a bit-serial CRC: slow, short, and written to be read. The fast
//! [`Encoder`](super::Encoder) and [`Decoder`](super::Decoder) are proven equal to it by
//! property tests (`tests/line_*.rs`).

use alloc::vec::Vec;

use super::bits::{BitSink, BitVec, Bits};
use super::config::{Coding, LineConfig};
use super::error::{EncodeError, LineError};
use super::frame::OwnedDecoded;
use super::{FLAG, MAX_FRAME_BYTES, MAX_TELEGRAM_BYTES, MIN_FRAME_BYTES};

/// ERRATA, Telegrams: ISO/IEC 3309 FCS, CRC-16 polynomial 1021H reflected (8408H), initial
/// value FFFFH, final XOR FFFFH, bits taken least significant first.
pub fn fcs(bytes: &[u8]) -> u16 {
    let mut crc: u16 = 0xFFFF;
    for &byte in bytes {
        for i in 0..8 {
            let bit = u16::from((byte >> i) & 1);
            let feedback = (crc ^ bit) & 1;
            crc >>= 1;
            if feedback == 1 {
                crc ^= 0x8408;
            }
        }
    }
    !crc
}

/// Bit-serial encoder with the same interface as the fast one.
#[derive(Debug, Clone)]
pub struct Encoder {
    config: LineConfig,
    level: bool,
}

impl Encoder {
    /// An encoder whose line starts dark.
    pub fn new(config: LineConfig) -> Self {
        Encoder {
            config,
            level: config.polarity.dark_level(),
        }
    }

    /// The pin level of the last bit written.
    pub fn level(&self) -> bool {
        self.level
    }

    /// One data bit as one pin level.
    fn send(&mut self, data: bool, out: &mut BitVec) {
        self.level = match self.config.coding {
            // NRZI: a 0 is a change of level, a 1 no change.
            Coding::Nrzi => self.level ^ !data,
            // NRZ: 1 = light on.
            Coding::Nrz => {
                let on = self.config.polarity.light_on_level();
                if data { on } else { !on }
            }
        };
        out.push(self.level);
    }

    /// Appends one frame for `telegram` (ADR and data); returns its line bits.
    pub fn encode(&mut self, telegram: &[u8], out: &mut BitVec) -> Result<u64, EncodeError> {
        if telegram.is_empty() {
            return Err(EncodeError::Empty);
        }
        if telegram.len() > MAX_TELEGRAM_BYTES {
            return Err(EncodeError::TooLong {
                len: telegram.len(),
                max: MAX_TELEGRAM_BYTES,
            });
        }
        let before = out.bit_len();
        let mut body: Vec<u8> = telegram.to_vec();
        body.extend_from_slice(&fcs(telegram).to_le_bytes());
        for i in (0..8).rev() {
            self.send((FLAG >> i) & 1 == 1, out);
        }
        let mut ones = 0;
        for byte in body {
            for i in 0..8 {
                let bit = (byte >> i) & 1 == 1;
                self.send(bit, out);
                if bit {
                    ones += 1;
                    if ones == 5 {
                        self.send(false, out);
                        ones = 0;
                    }
                } else {
                    ones = 0;
                }
            }
        }
        for i in (0..8).rev() {
            self.send((FLAG >> i) & 1 == 1, out);
        }
        Ok(out.bit_len() - before)
    }

    /// Appends `n` bits of idle filler (data 0s).
    pub fn idle(&mut self, n: u64, out: &mut BitVec) {
        for _ in 0..n {
            self.send(false, out);
        }
    }
}

/// Bit-serial streaming decoder with the same rules as the fast one.
#[derive(Debug, Clone)]
pub struct Decoder {
    config: LineConfig,
    pos: u64,
    prev: bool,
    /// Consecutive 1s so far; starts at 7 so that the first flag needs its leading 0.
    run: u32,
    open: bool,
    after_close: bool,
    start: u64,
    frame: Vec<bool>,
    mark: usize,
    ignored: u64,
}

impl Decoder {
    /// A decoder at bit position 0 that assumes a dark line before the first bit.
    pub fn new(config: LineConfig) -> Self {
        Decoder {
            config,
            pos: 0,
            prev: config.polarity.dark_level(),
            run: 7,
            open: false,
            after_close: false,
            start: 0,
            frame: Vec::new(),
            mark: 0,
            ignored: 0,
        }
    }

    /// How many stretches after a closing flag were dropped as noise.
    pub fn ignored(&self) -> u64 {
        self.ignored
    }

    /// Decodes a chunk, calling `sink` for every telegram or frame error.
    pub fn push<F: FnMut(OwnedDecoded)>(&mut self, bits: Bits<'_>, mut sink: F) {
        for pin in bits.iter() {
            let data = match self.config.coding {
                Coding::Nrzi => pin == self.prev,
                Coding::Nrz => pin == self.config.polarity.light_on_level(),
            };
            self.prev = pin;
            self.data_bit(data, &mut sink);
            self.pos += 1;
        }
    }

    fn data_bit<F: FnMut(OwnedDecoded)>(&mut self, data: bool, sink: &mut F) {
        let pos = self.pos;
        if data {
            self.run = self.run.saturating_add(1);
            if self.run == 7 {
                if self.open {
                    let error = LineError::Abort {
                        start: self.start,
                        at: pos,
                    };
                    self.fail(error, sink);
                }
            } else if self.run <= 5 && self.open {
                self.keep(true, sink);
            }
        } else {
            if self.run == 6 {
                self.flag(pos.saturating_sub(7), pos + 1, sink);
            } else if self.open {
                self.mark = self.frame.len();
                if self.run != 5 {
                    self.keep(false, sink);
                }
            }
            self.run = 0;
        }
    }

    fn keep<F: FnMut(OwnedDecoded)>(&mut self, bit: bool, sink: &mut F) {
        if self.frame.len() >= MAX_FRAME_BYTES * 8 + 6 {
            let error = LineError::TooLong {
                start: self.start,
                at: self.pos,
            };
            self.fail(error, sink);
        } else {
            self.frame.push(bit);
        }
    }

    fn fail<F: FnMut(OwnedDecoded)>(&mut self, error: LineError, sink: &mut F) {
        if self.after_close {
            self.ignored += 1;
        } else {
            let received = pack(&self.frame);
            sink(OwnedDecoded::Error { error, received });
        }
        self.open = false;
        self.after_close = false;
        self.frame.clear();
        self.mark = 0;
    }

    fn flag<F: FnMut(OwnedDecoded)>(&mut self, fstart: u64, fend: u64, sink: &mut F) {
        if self.open && self.mark > 0 {
            self.close(fstart, fend, sink);
        } else if !self.open {
            self.open = true;
            self.after_close = false;
        }
        self.start = fstart;
        self.frame.clear();
        self.mark = 0;
    }

    fn close<F: FnMut(OwnedDecoded)>(&mut self, fstart: u64, end: u64, sink: &mut F) {
        let start = self.start;
        let content = self.frame.get(..self.mark).unwrap_or(&[]);
        let bits = content.len() as u32;
        let bytes = pack(content);
        let result = if content.len() < MIN_FRAME_BYTES * 8 {
            Err((LineError::TooShort { start, end, bits }, bytes))
        } else if content.len() > MAX_FRAME_BYTES * 8 {
            Err((LineError::TooLong { start, at: fstart }, bytes))
        } else if content.len() % 8 != 0 {
            Err((LineError::NotWholeBytes { start, end, bits }, bytes))
        } else {
            let (telegram, received) = match bytes.split_last_chunk::<2>() {
                Some((telegram, fcs_bytes)) => (telegram.to_vec(), u16::from_le_bytes(*fcs_bytes)),
                None => (Vec::new(), 0),
            };
            let computed = fcs(&telegram);
            if received == computed {
                Ok(telegram)
            } else {
                let error = LineError::FcsMismatch {
                    start,
                    end,
                    received,
                    computed,
                };
                Err((error, telegram))
            }
        };
        match result {
            Ok(bytes) => {
                sink(OwnedDecoded::Telegram { start, end, bytes });
                self.after_close = true;
            }
            Err(_) if self.after_close => {
                self.ignored += 1;
                self.after_close = false;
            }
            Err((error, received)) => {
                sink(OwnedDecoded::Error { error, received });
                self.after_close = true;
            }
        }
    }
}

/// Whole bytes of data bits, least significant bit first; a partial last byte is dropped.
fn pack(bits: &[bool]) -> Vec<u8> {
    bits.chunks_exact(8)
        .map(|c| {
            c.iter()
                .enumerate()
                .fold(0u8, |b, (i, &bit)| b | (u8::from(bit) << i))
        })
        .collect()
}

/// Decodes a whole signal with the reference decoder.
pub fn decode_all(bits: Bits<'_>, config: LineConfig) -> Vec<OwnedDecoded> {
    let mut out = Vec::new();
    let mut decoder = Decoder::new(config);
    decoder.push(bits, |d| out.push(d));
    out
}
