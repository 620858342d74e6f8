//! Telegram headers and the end marker (410B §4.2.1, §4.2.3).

use crate::Variant;
use crate::bitfield::{bit, field};
use crate::error::RamError;

/// Which structure a header word 0 marks (ERRATA "telegram header marker bits").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HeaderKind {
    /// Bits 15, 14 = 0, 0: receive telegram header, 5 words (410B §4.2.1).
    Receive,
    /// Bits 15, 14 = 0, 1: transmit telegram header, 4 words (410B §4.2.1).
    Transmit,
    /// Bits 15, 14 = 1, 1: end marker, 2 words (410B §4.2.3).
    EndMarker,
}

impl HeaderKind {
    /// Classifies a header word 0 by its marker bits 15-14; 10 is invalid.
    // ERRATA "telegram header marker bits": 00 receive, 01 transmit, 11 end marker.
    pub const fn classify(word0: u16) -> Result<HeaderKind, RamError> {
        // Two bit tests, not a `match` on both bits: that becomes a jump table, whose
        // indirect jump mispredicts when a list alternates receive and transmit headers
        // (docs/performance.md, session 5).
        if word0 & 0x8000 == 0 {
            if word0 & 0x4000 == 0 {
                Ok(HeaderKind::Receive)
            } else {
                Ok(HeaderKind::Transmit)
            }
        } else if word0 & 0x4000 != 0 {
            Ok(HeaderKind::EndMarker)
        } else {
            Err(RamError::InvalidMarker { word0 })
        }
    }

    /// Number of words of the structure.
    pub const fn words(self) -> usize {
        match self {
            HeaderKind::Receive => RxHeader::WORDS,
            HeaderKind::Transmit => TxHeader::WORDS,
            HeaderKind::EndMarker => EndMarker::WORDS,
        }
    }

    /// The marker bits 15-14 in place.
    pub const fn marker(self) -> u16 {
        match self {
            HeaderKind::Receive => 0x0000,
            HeaderKind::Transmit => 0x4000,
            HeaderKind::EndMarker => 0xC000,
        }
    }
}

/// Where a telegram's data lives, from bits DMA and DBUF of header word 0 (410B §4.2.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Buffering {
    /// DMA = 0, DBUF = 0: one buffer in the RAM.
    Single,
    /// DMA = 0, DBUF = 1: two buffers in the RAM, VAL selects.
    Double,
    /// DMA = 1: data goes through the FIFOs; the container has only its control words.
    Dma,
}

impl Buffering {
    /// The buffering selected by DMA and DBUF (DBUF is ignored when DMA = 1).
    pub const fn from_bits(dma: bool, dbuf: bool) -> Buffering {
        match (dma, dbuf) {
            (true, _) => Buffering::Dma,
            (false, false) => Buffering::Single,
            (false, true) => Buffering::Double,
        }
    }

    /// Data words a container of `len` words occupies after its control words:
    /// LEN, 2 × LEN or none (410B §4.2.2, ERRATA "container words").
    pub const fn data_words(self, len: u16) -> u32 {
        match self {
            Buffering::Single => len as u32,
            Buffering::Double => 2 * len as u32,
            Buffering::Dma => 0,
        }
    }
}

/// Transmit enable EN (transmit header word 0 bits 12-11, 410B §4.2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[doc(alias = "EN")]
pub enum TxEnable {
    /// 0: the data telegram is not transmitted.
    Off = 0,
    /// 1: transmitted once; the chip sets EN to 0 after the telegram has started.
    Once = 1,
    /// 2: transmitted continuously.
    Continuous = 2,
    /// 3: transmitted only if the previously received telegram carried the expected
    /// address (PHAS12 = 1 and FLMDTADR = 1).
    OnAddress = 3,
}

impl TxEnable {
    /// The EN value of a 2-bit code (higher bits ignored).
    pub const fn from_code(code: u16) -> TxEnable {
        match code & 3 {
            0 => TxEnable::Off,
            1 => TxEnable::Once,
            2 => TxEnable::Continuous,
            _ => TxEnable::OnAddress,
        }
    }
}

fn take<const N: usize>(words: &[u16]) -> Result<[u16; N], RamError> {
    match words.get(..N) {
        Some(slice) => {
            let mut out = [0u16; N];
            out.copy_from_slice(slice);
            Ok(out)
        }
        None => Err(RamError::TooShort {
            needed: N,
            got: words.len(),
        }),
    }
}

const fn expect_kind(word0: u16, expected: HeaderKind) -> Result<(), RamError> {
    match HeaderKind::classify(word0) {
        Ok(found) => {
            if found as u8 == expected as u8 {
                Ok(())
            } else {
                Err(RamError::WrongKind { expected, found })
            }
        }
        Err(e) => Err(e),
    }
}

/// Header of a receive telegram, 5 words (410B §4.2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct RxHeader {
    /// ADR (word 0 bits 7-0): telegram address; with ACHK = 0 the received address is
    /// stored here.
    pub adr: u8,
    /// DMA (0.8): data through DMA instead of the RAM.
    pub dma: bool,
    /// DBUF (0.9): double buffer.
    pub dbuf: bool,
    /// VAL (0.10): data valid (single/DMA) or valid buffer (double); toggled by the
    /// controller at the beginning and end of receive telegrams.
    pub val: bool,
    /// ACHK (0.11): receive only with the expected address.
    pub achk: bool,
    /// TCHK (0.12): the time of receiving is checked.
    pub tchk: bool,
    /// RERR (0.13): the last telegram was errored or not received.
    pub rerr: bool,
    /// TRT (word 1): start of the telegram in µs after the end of MST.
    pub trt: u16,
    /// TLEN (word 2): length of the telegram in data words (not including address).
    pub tlen: u16,
    /// PT (word 3, bits 9-0 on the 410B, 10-0 on the 816): word address of the next
    /// header or the end marker.
    pub pt: u16,
    /// Word 3 bits outside PT ("(Not used)"), kept in place.
    pub pt_reserved: u16,
    /// NERR (word 4): error counter.
    pub nerr: u16,
}

impl RxHeader {
    /// Number of words.
    pub const WORDS: usize = 5;

    /// Decodes the 5 words; fails unless word 0 marks a receive header.
    pub fn from_words(variant: Variant, words: [u16; 5]) -> Result<Self, RamError> {
        let [w0, trt, tlen, w3, nerr] = words;
        expect_kind(w0, HeaderKind::Receive)?;
        // 410B §4.2.1 receive header, word 0: ADR 7-0, DMA 8, DBUF 9, VAL 10, ACHK 11,
        // TCHK 12, RERR 13, marker bits 14 = 0, 15 = 0.
        let mask = variant.pointer_mask();
        Ok(RxHeader {
            adr: w0 as u8,
            dma: bit(w0, 8),
            dbuf: bit(w0, 9),
            val: bit(w0, 10),
            achk: bit(w0, 11),
            tchk: bit(w0, 12),
            rerr: bit(w0, 13),
            trt,
            tlen,
            pt: w3 & mask,
            pt_reserved: w3 & !mask,
            nerr,
        })
    }

    /// Decodes the first 5 words of `words`.
    pub fn decode(variant: Variant, words: &[u16]) -> Result<Self, RamError> {
        Self::from_words(variant, take(words)?)
    }

    /// Encodes to 5 words. PT is cut to the variant's pointer width and
    /// `pt_reserved` to the bits outside it.
    pub const fn to_words(self, variant: Variant) -> [u16; 5] {
        let mask = variant.pointer_mask();
        let w0 = HeaderKind::Receive.marker()
            | self.adr as u16
            | (self.dma as u16) << 8
            | (self.dbuf as u16) << 9
            | (self.val as u16) << 10
            | (self.achk as u16) << 11
            | (self.tchk as u16) << 12
            | (self.rerr as u16) << 13;
        [
            w0,
            self.trt,
            self.tlen,
            (self.pt & mask) | (self.pt_reserved & !mask),
            self.nerr,
        ]
    }

    /// Where the data of this telegram lives.
    pub const fn buffering(self) -> Buffering {
        Buffering::from_bits(self.dma, self.dbuf)
    }
}

/// Header of a transmit telegram, 4 words (410B §4.2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TxHeader {
    /// ADR (word 0 bits 7-0): telegram address.
    pub adr: u8,
    /// DMA (0.8): data through DMA instead of the RAM.
    pub dma: bool,
    /// DBUF (0.9): double buffer.
    pub dbuf: bool,
    /// VAL (0.10): with double buffering, buffer 1 (not 0) is valid; set by the processor.
    pub val: bool,
    /// EN (0.12-11): transmit enable.
    pub en: TxEnable,
    /// Bit 13 of word 0 ("(Not used)"), kept.
    pub reserved13: bool,
    /// TRT (word 1): start of the telegram in µs after the end of MST.
    pub trt: u16,
    /// TLEN (word 2): length of the telegram in data words (not including address).
    pub tlen: u16,
    /// PT (word 3, bits 9-0 on the 410B, 10-0 on the 816): word address of the next
    /// header or the end marker.
    pub pt: u16,
    /// Word 3 bits outside PT ("(Not used)"), kept in place.
    pub pt_reserved: u16,
}

impl TxHeader {
    /// Number of words.
    pub const WORDS: usize = 4;

    /// Decodes the 4 words; fails unless word 0 marks a transmit header.
    pub fn from_words(variant: Variant, words: [u16; 4]) -> Result<Self, RamError> {
        let [w0, trt, tlen, w3] = words;
        expect_kind(w0, HeaderKind::Transmit)?;
        // 410B §4.2.1 transmit header, word 0: ADR 7-0, DMA 8, DBUF 9, VAL 10, EN 12-11,
        // 13 not used, marker bit 14 = 1, bit 15 = 0.
        let mask = variant.pointer_mask();
        Ok(TxHeader {
            adr: w0 as u8,
            dma: bit(w0, 8),
            dbuf: bit(w0, 9),
            val: bit(w0, 10),
            en: TxEnable::from_code(field(w0, 11, 2)),
            reserved13: bit(w0, 13),
            trt,
            tlen,
            pt: w3 & mask,
            pt_reserved: w3 & !mask,
        })
    }

    /// Decodes the first 4 words of `words`.
    pub fn decode(variant: Variant, words: &[u16]) -> Result<Self, RamError> {
        Self::from_words(variant, take(words)?)
    }

    /// Encodes to 4 words. PT is cut to the variant's pointer width and
    /// `pt_reserved` to the bits outside it.
    pub const fn to_words(self, variant: Variant) -> [u16; 4] {
        let mask = variant.pointer_mask();
        let w0 = HeaderKind::Transmit.marker()
            | self.adr as u16
            | (self.dma as u16) << 8
            | (self.dbuf as u16) << 9
            | (self.val as u16) << 10
            | (self.en as u16) << 11
            | (self.reserved13 as u16) << 13;
        [
            w0,
            self.trt,
            self.tlen,
            (self.pt & mask) | (self.pt_reserved & !mask),
        ]
    }

    /// Where the data of this telegram lives.
    pub const fn buffering(self) -> Buffering {
        Buffering::from_bits(self.dma, self.dbuf)
    }
}

impl Default for TxHeader {
    fn default() -> Self {
        TxHeader {
            adr: 0,
            dma: false,
            dbuf: false,
            val: false,
            en: TxEnable::Off,
            reserved13: false,
            trt: 0,
            tlen: 0,
            pt: 0,
            pt_reserved: 0,
        }
    }
}

/// The end marker, 2 words (410B §4.2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct EndMarker {
    /// Word 0 bits 13-0 ("(Not used)"), kept.
    pub reserved: u16,
    /// TEND (word 1): time after the end of MST at which the last telegram has ended, µs.
    pub tend: u16,
}

impl EndMarker {
    /// Number of words.
    pub const WORDS: usize = 2;

    /// Decodes the 2 words; fails unless word 0 marks an end marker.
    pub fn from_words(words: [u16; 2]) -> Result<Self, RamError> {
        let [w0, tend] = words;
        expect_kind(w0, HeaderKind::EndMarker)?;
        Ok(EndMarker {
            reserved: w0 & 0x3FFF,
            tend,
        })
    }

    /// Decodes the first 2 words of `words`.
    pub fn decode(words: &[u16]) -> Result<Self, RamError> {
        Self::from_words(take(words)?)
    }

    /// Encodes to 2 words (`reserved` is cut to bits 13-0).
    pub const fn to_words(self) -> [u16; 2] {
        [
            HeaderKind::EndMarker.marker() | (self.reserved & 0x3FFF),
            self.tend,
        ]
    }
}

/// Any structure a header pointer (COMPTn, PT) can point at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Header {
    /// A receive telegram header.
    Receive(RxHeader),
    /// A transmit telegram header.
    Transmit(TxHeader),
    /// The end marker of a transmission block.
    End(EndMarker),
}

impl Header {
    /// Classifies `words[0]` and decodes the structure it marks from `words`.
    pub fn decode(variant: Variant, words: &[u16]) -> Result<Header, RamError> {
        let word0 = match words.first() {
            Some(w) => *w,
            None => return Err(RamError::TooShort { needed: 1, got: 0 }),
        };
        Ok(match HeaderKind::classify(word0)? {
            HeaderKind::Receive => Header::Receive(RxHeader::decode(variant, words)?),
            HeaderKind::Transmit => Header::Transmit(TxHeader::decode(variant, words)?),
            HeaderKind::EndMarker => Header::End(EndMarker::decode(words)?),
        })
    }

    /// The kind of this structure.
    pub const fn kind(&self) -> HeaderKind {
        match self {
            Header::Receive(_) => HeaderKind::Receive,
            Header::Transmit(_) => HeaderKind::Transmit,
            Header::End(_) => HeaderKind::EndMarker,
        }
    }

    /// Encodes into the start of `out`; returns the number of words written.
    pub fn encode(&self, variant: Variant, out: &mut [u16]) -> Result<usize, RamError> {
        let n = self.kind().words();
        let Some(dst) = out.get_mut(..n) else {
            return Err(RamError::TooShort {
                needed: n,
                got: out.len(),
            });
        };
        match self {
            Header::Receive(h) => dst.copy_from_slice(&h.to_words(variant)),
            Header::Transmit(h) => dst.copy_from_slice(&h.to_words(variant)),
            Header::End(h) => dst.copy_from_slice(&h.to_words()),
        }
        Ok(n)
    }

    /// PT of a telegram header (`None` for the end marker).
    pub const fn pt(&self) -> Option<u16> {
        match self {
            Header::Receive(h) => Some(h.pt),
            Header::Transmit(h) => Some(h.pt),
            Header::End(_) => None,
        }
    }
}
