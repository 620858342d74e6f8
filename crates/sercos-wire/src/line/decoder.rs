//! Fast, streaming, table-driven decoder: line bits → telegrams.
//!
//! The frame rules (ERRATA, Telegrams: flag 7EH, ADR, data, FCS, flag 7EH; a 0 inserted after
//! five consecutive 1s; bytes least significant bit first) are applied a byte of line bits at a
//! time through a table; a byte in which a flag or an abort ends falls back to the bit-serial
//! step, so both paths share one definition of every event. The reading of noise, idle filler
//! and shared flags is in `docs/spec-notes.md`, "Line coding".

use super::bits::Bits;
use super::config::LineConfig;
use super::error::LineError;
use super::fcs::{FCS_LEN, fcs};
use super::frame::{Decoded, Frame};
use super::nrzi::{decode_bit, decode_byte};
use super::{FLAG_BITS, MAX_FRAME_BYTES, MIN_FRAME_BYTES};

/// Most bits between the flags of an acceptable frame.
const LIMIT_BITS: u32 = (MAX_FRAME_BYTES * 8) as u32;
/// Bits a frame may hold before its closing flag is recognised: the flag's leading 0 and five
/// 1s are taken as data until the sixth 1 shows them to be a flag. One bit more proves the
/// frame too long.
const PUSH_LIMIT: u32 = LIMIT_BITS + 6;
/// Frame buffer: room for `PUSH_LIMIT` bits.
const BUF: usize = MAX_FRAME_BYTES + 1;
/// Run length that stands for "seven or more 1s", also the state before the first bit, so that
/// a flag needs its own leading 0.
const ONES_ABORTED: u8 = 7;

/// Table entry: how 8 data bits (first bit most significant) change the decoder when no flag
/// or abort ends among them.
#[derive(Clone, Copy)]
struct Step {
    /// Data bits kept, first bit in bit 0 (bytes are least significant bit first).
    bits: u8,
    /// Number of data bits kept.
    n: u8,
    /// Run of 1s after the byte (0..=7, 7 = seven or more).
    ones: u8,
    /// Bits kept before the last 0 of the byte, or `NO_ZERO`.
    mark: u8,
    /// A flag or an abort ends at bit `pre` of this byte: the fields above describe the bits
    /// before it, and the bit-serial path takes the rest.
    event: bool,
    /// Bits described by the fields above (8 unless `event`).
    pre: u8,
}

const NO_ZERO: u8 = 0xFF;

static STEP: [[Step; 256]; 8] = build_step_table();

const fn build_step_table() -> [[Step; 256]; 8] {
    let mut table = [[Step {
        bits: 0,
        n: 0,
        ones: 0,
        mark: NO_ZERO,
        event: false,
        pre: 8,
    }; 256]; 8];
    let mut start = 0;
    while start < 8 {
        let mut d = 0;
        while d < 256 {
            let mut s = Step {
                bits: 0,
                n: 0,
                ones: start as u8,
                mark: NO_ZERO,
                event: false,
                pre: 8,
            };
            let mut i = 0;
            while i < 8 {
                let bit = (d >> (7 - i)) & 1;
                if bit == 1 {
                    if s.ones == 6 {
                        s.event = true; // abort
                        s.pre = i as u8;
                        break;
                    }
                    if s.ones < ONES_ABORTED {
                        s.ones += 1;
                        if s.ones <= 5 {
                            s.bits |= 1 << s.n;
                            s.n += 1;
                        }
                    }
                } else {
                    if s.ones == 6 {
                        s.event = true; // flag
                        s.pre = i as u8;
                        break;
                    }
                    s.mark = s.n;
                    if s.ones != 5 {
                        s.n += 1;
                    }
                    s.ones = 0;
                }
                i += 1;
            }
            table[start][d] = s;
            d += 1;
        }
        start += 1;
    }
    table
}

/// Streaming decoder. Feed it the line signal in chunks of any size with [`Decoder::push`];
/// it calls back with every telegram and every frame error, with absolute bit positions.
///
/// After an error it hunts for the next flag and loses nothing that follows. Telegrams may
/// share a flag. What lies between a closing flag and the next opening flag is noise and
/// ignored (`docs/spec-notes.md`, "Line coding").
#[derive(Clone)]
pub struct Decoder {
    config: LineConfig,
    /// Absolute position of the next bit.
    pos: u64,
    /// Pin level of the last bit.
    prev: bool,
    /// Run of 1s in the data bits (7 = seven or more).
    ones: u8,
    /// Inside a frame: an opening flag has been seen.
    open: bool,
    /// The flag that opened the current frame closed the previous one.
    after_close: bool,
    /// First bit of the opening flag.
    start: u64,
    /// Data bits kept in this frame.
    len: u32,
    /// Data bits kept before the last 0 that was not the end of a flag.
    mark: u32,
    acc: u32,
    nacc: u32,
    flushed: usize,
    buf: [u8; BUF],
    ignored: u64,
}

impl core::fmt::Debug for Decoder {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Decoder")
            .field("config", &self.config)
            .field("pos", &self.pos)
            .field("open", &self.open)
            .field("start", &self.start)
            .field("len", &self.len)
            .field("ignored", &self.ignored)
            .finish_non_exhaustive()
    }
}

impl Decoder {
    /// A decoder at bit position 0 that assumes a dark line before the first bit
    /// (`docs/spec-notes.md`, "Line coding").
    pub fn new(config: LineConfig) -> Self {
        Decoder {
            config,
            pos: 0,
            prev: config.polarity.dark_level(),
            ones: ONES_ABORTED,
            open: false,
            after_close: false,
            start: 0,
            len: 0,
            mark: 0,
            acc: 0,
            nacc: 0,
            flushed: 0,
            buf: [0; BUF],
            ignored: 0,
        }
    }

    /// The configuration.
    pub fn config(&self) -> LineConfig {
        self.config
    }

    /// Absolute position of the next bit to be pushed (bits consumed so far).
    pub fn position(&self) -> u64 {
        self.pos
    }

    /// Whether a frame is open (an opening flag seen, no closing flag yet).
    pub fn in_frame(&self) -> bool {
        self.open
    }

    /// The frame being received, once it has data (an opening flag and data bits, no closing
    /// flag or abort yet): the first bit of its opening flag and its whole bytes so far (ADR
    /// first; the FCS is not told from data before the closing flag). A telegram whose end the
    /// bits still to come decide. `None` between frames and right after a flag.
    pub fn frame_in_progress(&self) -> Option<(u64, &[u8])> {
        if !self.open || self.len == 0 {
            return None;
        }
        Some((self.start, self.buf.get(..self.flushed).unwrap_or(&[])))
    }

    /// How many stretches between a closing flag and the next flag were dropped as noise.
    pub fn ignored(&self) -> u64 {
        self.ignored
    }

    /// Decodes the next chunk of the line signal and calls `sink` for every telegram or frame
    /// error that ends in it.
    pub fn push<F: FnMut(Decoded<'_>)>(&mut self, bits: Bits<'_>, mut sink: F) {
        let (bytes, offset, len) = bits.raw();
        let mut i = 0usize;
        // Leading bits up to a byte boundary of the input, one at a time.
        while i < len && (offset + i) % 8 != 0 {
            self.pin(bits.get(i).unwrap_or(false), &mut sink);
            i += 1;
        }
        // Whole bytes.
        let first = (offset + i) / 8;
        let whole = (len - i) / 8;
        if let Some(body) = bytes.get(first..first + whole) {
            for &pins in body {
                let d = decode_byte(self.config, pins, &mut self.prev);
                self.byte(d, &mut sink);
            }
            i += whole * 8;
        }
        // Trailing bits.
        while i < len {
            self.pin(bits.get(i).unwrap_or(false), &mut sink);
            i += 1;
        }
    }

    /// One pin level.
    fn pin<F: FnMut(Decoded<'_>)>(&mut self, pin: bool, sink: &mut F) {
        let d = decode_bit(self.config, pin, &mut self.prev);
        let pos = self.pos;
        self.bit(d, pos, sink);
        self.pos += 1;
    }

    /// Eight data bits, first bit most significant, through the table when possible.
    #[inline]
    fn byte<F: FnMut(Decoded<'_>)>(&mut self, d: u8, sink: &mut F) {
        let pos = self.pos;
        self.pos += 8;
        let s = match STEP.get(usize::from(self.ones)) {
            Some(row) => row[usize::from(d)],
            None => Step {
                bits: 0,
                n: 0,
                ones: 0,
                mark: NO_ZERO,
                event: true,
                pre: 0,
            },
        };
        if self.open && self.len + 8 > PUSH_LIMIT {
            for k in 0..8u8 {
                self.bit((d >> (7 - k)) & 1 == 1, pos + u64::from(k), sink);
            }
            return;
        }
        self.ones = s.ones;
        if self.open {
            if s.mark != NO_ZERO {
                self.mark = self.len + u32::from(s.mark);
            }
            self.acc |= u32::from(s.bits) << self.nacc;
            self.nacc += u32::from(s.n);
            self.len += u32::from(s.n);
            self.flush_byte();
        }
        if s.event {
            for k in s.pre..8 {
                self.bit((d >> (7 - k)) & 1 == 1, pos + u64::from(k), sink);
            }
        }
    }

    /// Moves a completed byte from the accumulator to the frame buffer.
    #[inline]
    fn flush_byte(&mut self) {
        if self.nacc >= 8 {
            if let Some(b) = self.buf.get_mut(self.flushed) {
                *b = self.acc as u8;
            }
            self.flushed += 1;
            self.acc >>= 8;
            self.nacc -= 8;
        }
    }

    /// The bit-serial step: one data bit at absolute position `pos`.
    fn bit<F: FnMut(Decoded<'_>)>(&mut self, d: bool, pos: u64, sink: &mut F) {
        if d {
            match self.ones {
                // ERRATA, Telegrams (HDLC framing): a seventh consecutive 1 aborts the frame.
                6 => {
                    self.ones = ONES_ABORTED;
                    self.abort(pos, sink);
                }
                ONES_ABORTED => {}
                _ => {
                    self.ones += 1;
                    // The sixth 1 is held back: it belongs to a flag or an abort.
                    if self.ones <= 5 && self.open {
                        self.keep(true, pos, sink);
                    }
                }
            }
        } else {
            let before = self.ones;
            self.ones = 0;
            if before == 6 {
                // ERRATA, Telegrams: 01111110 is the flag; it began 7 bits ago.
                self.flag(pos.saturating_sub(FLAG_BITS - 1), pos + 1, sink);
            } else if self.open {
                self.mark = self.len;
                // ERRATA, Telegrams: the 0 after five consecutive 1s was inserted; drop it.
                if before != 5 {
                    self.keep(false, pos, sink);
                }
            }
        }
    }

    /// Keeps one data bit of the open frame, or ends the frame as too long.
    fn keep<F: FnMut(Decoded<'_>)>(&mut self, bit: bool, pos: u64, sink: &mut F) {
        if self.len >= PUSH_LIMIT {
            let error = LineError::TooLong {
                start: self.start,
                at: pos,
            };
            self.fail_open(error, sink);
            return;
        }
        self.acc |= u32::from(bit) << self.nacc;
        self.nacc += 1;
        self.len += 1;
        self.flush_byte();
    }

    /// Seven 1s: the open frame, if any, is lost; hunt for the next flag.
    fn abort<F: FnMut(Decoded<'_>)>(&mut self, pos: u64, sink: &mut F) {
        if self.open {
            let error = LineError::Abort {
                start: self.start,
                at: pos,
            };
            self.fail_open(error, sink);
        }
    }

    /// Ends the open frame with `error` (reported unless it is noise after a closing flag).
    fn fail_open<F: FnMut(Decoded<'_>)>(&mut self, error: LineError, sink: &mut F) {
        if self.after_close {
            self.ignored += 1;
        } else {
            let received = self.buf.get(..self.flushed).unwrap_or(&[]);
            sink(Decoded::Error { error, received });
        }
        self.open = false;
        self.after_close = false;
        self.reset_frame();
    }

    fn reset_frame(&mut self) {
        self.len = 0;
        self.mark = 0;
        self.acc = 0;
        self.nacc = 0;
        self.flushed = 0;
    }

    /// A flag occupying `fstart..fend`: it closes the open frame and opens the next.
    fn flag<F: FnMut(Decoded<'_>)>(&mut self, fstart: u64, fend: u64, sink: &mut F) {
        if self.open && self.mark > 0 {
            self.close(fend, sink);
        } else if !self.open {
            self.open = true;
            self.after_close = false;
        }
        // Two flags in a row: the later one opens the frame.
        self.start = fstart;
        self.reset_frame();
    }

    /// Validates the frame that a flag ending at `fend` closes, and reports it.
    fn close<F: FnMut(Decoded<'_>)>(&mut self, fend: u64, sink: &mut F) {
        // Bits of the flag's leading 0 and five 1s were kept as data: cut back to the mark.
        if self.nacc > 0
            && let Some(b) = self.buf.get_mut(self.flushed)
        {
            *b = self.acc as u8;
        }
        let start = self.start;
        let bits = self.mark;
        let whole = (bits / 8) as usize;
        let outcome = if bits < (MIN_FRAME_BYTES * 8) as u32 {
            Err((
                LineError::TooShort {
                    start,
                    end: fend,
                    bits,
                },
                whole,
            ))
        } else if bits > LIMIT_BITS {
            let at = fend - FLAG_BITS;
            Err((LineError::TooLong { start, at }, whole))
        } else if bits % 8 != 0 {
            Err((
                LineError::NotWholeBytes {
                    start,
                    end: fend,
                    bits,
                },
                whole,
            ))
        } else {
            let n = whole - FCS_LEN;
            let telegram = self.buf.get(..n).unwrap_or(&[]);
            let received = match self.buf.get(n..whole) {
                Some(&[lo, hi]) => u16::from_le_bytes([lo, hi]),
                _ => 0,
            };
            // ERRATA, Telegrams: FCS over ADR and data, sent low byte first.
            let computed = fcs(telegram);
            if received == computed {
                Ok(n)
            } else {
                let error = LineError::FcsMismatch {
                    start,
                    end: fend,
                    received,
                    computed,
                };
                Err((error, n))
            }
        };
        match outcome {
            Ok(n) => {
                let bytes = self.buf.get(..n).unwrap_or(&[]);
                sink(Decoded::Telegram(Frame {
                    start,
                    end: fend,
                    bytes,
                }));
                self.after_close = true;
            }
            Err(_) if self.after_close => {
                // Noise between a closing flag and the next opening flag.
                self.ignored += 1;
                self.after_close = false;
            }
            Err((error, r)) => {
                let received = self.buf.get(..r).unwrap_or(&[]);
                sink(Decoded::Error { error, received });
                self.after_close = true;
            }
        }
    }
}

/// Decodes a whole signal at once (with the `alloc` feature).
#[cfg(feature = "alloc")]
pub fn decode_all(bits: Bits<'_>, config: LineConfig) -> alloc::vec::Vec<super::OwnedDecoded> {
    let mut out = alloc::vec::Vec::new();
    let mut decoder = Decoder::new(config);
    decoder.push(bits, |d| out.push(d.to_owned()));
    out
}
