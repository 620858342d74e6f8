//! Service containers (410B §4.2.4): five control words and a buffer.
//!
//! The coding of the control words depends on the mode of the service channel, which
//! the data container gives (SCMASTER, 410B §4.2.2). The buffer pointers WRDATPT,
//! WRDATLAST, RDDATPT and RDDATLAST (8 bits each) are word offsets from the start of
//! the service container, so the buffer starts at offset 5 ([`SC_BUFFER_OFFSET`]) and
//! holds at most 251 words ([`SC_BUFFER_MAX_WORDS`]) (reading chosen because Figure 14
//! is missing; see `docs/spec-notes.md`).

use crate::Variant;
use crate::bitfield::{bit, field};
use crate::error::{FieldError, RamError};

/// Number of control words of a service container (410B §4.2.4).
pub const SC_CONTROL_WORDS: usize = 5;

/// Offset of the first buffer word from the start of the service container: the
/// smallest meaningful value of WRDATPT/RDDATPT (reading chosen, spec-notes).
pub const SC_BUFFER_OFFSET: u8 = 5;

/// Largest buffer a service container can address with 8-bit offsets: offsets 5..=255.
pub const SC_BUFFER_MAX_WORDS: u16 = 256 - SC_BUFFER_OFFSET as u16;

/// Word address in the RAM of the word at `offset` in the service container that
/// starts at `scpt` (wrapping within the variant's RAM, as the chip's A10-1/A11-1 do).
pub const fn sc_word_address(variant: Variant, scpt: u16, offset: u8) -> u16 {
    scpt.wrapping_add(offset as u16) & variant.ram_address_mask()
}

/// NINFO_WRITE / NINFO_READ: number of info words in a buffer, 1 to 4, coded in 2 bits
/// as count − 1 (reading chosen, see spec-notes: a zeroed RAM gives the SERCOS
/// standard of one info word).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[doc(alias("NINFO_WRITE", "NINFO_READ"))]
pub struct NInfo(u8);

impl NInfo {
    /// The value for `count` info words (1–4).
    pub const fn from_count(count: u8) -> Result<NInfo, FieldError> {
        if count >= 1 && count <= 4 {
            Ok(NInfo(count - 1))
        } else {
            Err(FieldError {
                field: "NINFO",
                value: count as u16,
                width: 2,
            })
        }
    }

    /// The value of a 2-bit code (higher bits ignored).
    pub const fn from_code(code: u8) -> NInfo {
        NInfo(code & 3)
    }

    /// The 2-bit code.
    pub const fn code(self) -> u8 {
        self.0
    }

    /// Number of info words, 1–4.
    pub const fn count(self) -> u8 {
        self.0 + 1
    }
}

/// Control words 2 and 3, the same in both modes (410B §4.2.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ScPointers {
    /// WRDATPT (word 2 bits 7-0): present position in the write buffer.
    pub wrdatpt: u8,
    /// WRDATLAST (word 2 bits 15-8): last position in the write buffer.
    pub wrdatlast: u8,
    /// RDDATPT (word 3 bits 7-0): present position in the read buffer.
    pub rddatpt: u8,
    /// RDDATLAST (word 3 bits 15-8): last position in the read buffer.
    pub rddatlast: u8,
}

impl ScPointers {
    const fn from_words(w2: u16, w3: u16) -> Self {
        ScPointers {
            wrdatpt: w2 as u8,
            wrdatlast: (w2 >> 8) as u8,
            rddatpt: w3 as u8,
            rddatlast: (w3 >> 8) as u8,
        }
    }

    const fn to_words(self) -> [u16; 2] {
        [
            self.wrdatpt as u16 | (self.wrdatlast as u16) << 8,
            self.rddatpt as u16 | (self.rddatlast as u16) << 8,
        ]
    }
}

const fn bool16(b: bool, at: u8) -> u16 {
    (b as u16) << at
}

fn take5(words: &[u16]) -> Result<[u16; 5], RamError> {
    match words {
        [a, b, c, d, e, ..] => Ok([*a, *b, *c, *d, *e]),
        _ => Err(RamError::TooShort {
            needed: SC_CONTROL_WORDS,
            got: words.len(),
        }),
    }
}

/// The five control words of a service container in master mode (SCMASTER = 1,
/// 410B §4.2.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ScMaster {
    /// HS_MDT (0.0): handshake bit in MDT.
    pub hs_mdt: bool,
    /// L/S_MDT (0.1): read/write in MDT.
    #[doc(alias = "L/S_MDT")]
    pub ls_mdt: bool,
    /// END_MDT (0.2): end in MDT.
    pub end_mdt: bool,
    /// ELEM_MDT (0.5-3): data element type in MDT.
    pub elem_mdt: u8,
    /// SETEND (0.6): END_MDT is to be set.
    pub setend: bool,
    /// M_BUSY (0.7): the container waits for the microprocessor.
    pub m_busy: bool,
    /// NINFO_WRITE (0.9-8): number of info words in the write buffer.
    pub ninfo_write: NInfo,
    /// INT_ERR (0.12): slave reports error.
    pub int_err: bool,
    /// INT_END_WRBUF (0.13): end of write buffer reached.
    pub int_end_wrbuf: bool,
    /// INT_END_RDBUF (0.14): end of read buffer reached.
    pub int_end_rdbuf: bool,
    /// HS_AT (1.0): handshake bit in AT.
    pub hs_at: bool,
    /// BUSY_AT (1.1): busy bit in AT.
    pub busy_at: bool,
    /// ERR_AT (1.2): error bit in AT.
    pub err_at: bool,
    /// CMD_AT (1.3): command modification bit in AT (ERRATA "service info").
    pub cmd_at: bool,
    /// RECERR (1.7): the last transmission was erroneous.
    pub recerr: bool,
    /// NINFO_READ (1.9-8): number of info words in the read buffer.
    pub ninfo_read: NInfo,
    /// Words 2 and 3: buffer pointers.
    pub pointers: ScPointers,
    /// ERR_CNT (4.7-0): error counter.
    pub err_cnt: u8,
    /// BUSY_CNT (4.8): the error counter counts BUSY cycles (1) or handshake
    /// differences (0).
    pub busy_cnt: bool,
    /// INT_SC_ERR (4.9): interrupt due to protocol error.
    pub int_sc_err: bool,
    /// INT_HS_TIMEOUT (4.10): interrupt due to handshake timeout.
    pub int_hs_timeout: bool,
    /// INT_BUSY_TIMEOUT (4.11): interrupt BUSY timeout.
    pub int_busy_timeout: bool,
    /// INT_CMD (4.12): the slave has set the command modification bit.
    pub int_cmd: bool,
    /// The "(Not used)" bits of words 0–4 in place (masks [`ScMaster::RESERVED`]).
    pub reserved: [u16; 5],
}

impl ScMaster {
    /// "(Not used)" bits per word: 0.10-11, 0.15; 1.4-6, 1.10-15; 4.13-15.
    pub const RESERVED: [u16; 5] = [0x8C00, 0xFC70, 0, 0, 0xE000];

    /// Decodes the five control words (never fails).
    pub const fn from_words(words: [u16; 5]) -> Self {
        let [w0, w1, w2, w3, w4] = words;
        let r = Self::RESERVED;
        ScMaster {
            hs_mdt: bit(w0, 0),
            ls_mdt: bit(w0, 1),
            end_mdt: bit(w0, 2),
            elem_mdt: field(w0, 3, 3) as u8,
            setend: bit(w0, 6),
            m_busy: bit(w0, 7),
            ninfo_write: NInfo::from_code(field(w0, 8, 2) as u8),
            int_err: bit(w0, 12),
            int_end_wrbuf: bit(w0, 13),
            int_end_rdbuf: bit(w0, 14),
            hs_at: bit(w1, 0),
            busy_at: bit(w1, 1),
            err_at: bit(w1, 2),
            cmd_at: bit(w1, 3),
            recerr: bit(w1, 7),
            ninfo_read: NInfo::from_code(field(w1, 8, 2) as u8),
            pointers: ScPointers::from_words(w2, w3),
            err_cnt: w4 as u8,
            busy_cnt: bit(w4, 8),
            int_sc_err: bit(w4, 9),
            int_hs_timeout: bit(w4, 10),
            int_busy_timeout: bit(w4, 11),
            int_cmd: bit(w4, 12),
            reserved: [w0 & r[0], w1 & r[1], w2 & r[2], w3 & r[3], w4 & r[4]],
        }
    }

    /// Decodes the first five words of `words`.
    pub fn decode(words: &[u16]) -> Result<Self, RamError> {
        Ok(Self::from_words(take5(words)?))
    }

    /// Encodes the five control words (ELEM_MDT is cut to 3 bits, `reserved` to the
    /// reserved bits).
    pub const fn to_words(self) -> [u16; 5] {
        let r = Self::RESERVED;
        let w0 = bool16(self.hs_mdt, 0)
            | bool16(self.ls_mdt, 1)
            | bool16(self.end_mdt, 2)
            | ((self.elem_mdt as u16) & 7) << 3
            | bool16(self.setend, 6)
            | bool16(self.m_busy, 7)
            | (self.ninfo_write.code() as u16) << 8
            | bool16(self.int_err, 12)
            | bool16(self.int_end_wrbuf, 13)
            | bool16(self.int_end_rdbuf, 14)
            | (self.reserved[0] & r[0]);
        let w1 = bool16(self.hs_at, 0)
            | bool16(self.busy_at, 1)
            | bool16(self.err_at, 2)
            | bool16(self.cmd_at, 3)
            | bool16(self.recerr, 7)
            | (self.ninfo_read.code() as u16) << 8
            | (self.reserved[1] & r[1]);
        let [w2, w3] = self.pointers.to_words();
        let w4 = self.err_cnt as u16
            | bool16(self.busy_cnt, 8)
            | bool16(self.int_sc_err, 9)
            | bool16(self.int_hs_timeout, 10)
            | bool16(self.int_busy_timeout, 11)
            | bool16(self.int_cmd, 12)
            | (self.reserved[4] & r[4]);
        [w0, w1, w2, w3, w4]
    }
}

/// The five control words of a service container in slave mode (SCMASTER = 0,
/// 410B §4.2.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ScSlave {
    /// HS_AT (0.0): handshake bit in AT.
    pub hs_at: bool,
    /// BUSY_AT (0.1): busy bit in AT, also waiting for the microprocessor.
    pub busy_at: bool,
    /// ERR_AT (0.2): error bit in AT.
    pub err_at: bool,
    /// CMD_AT (0.3): command modification bit in AT (the datasheet's cell is garbled
    /// as "Error bit in AT"; ERRATA and task reading).
    pub cmd_at: bool,
    /// ELEM (0.6-4): data element of the present transmission.
    pub elem: u8,
    /// L/S (0.7): read (0) / write (1) of the present transmission.
    #[doc(alias = "L/S")]
    pub ls: bool,
    /// NINFO_WRITE (0.9-8): number of info words in the write buffer.
    pub ninfo_write: NInfo,
    /// INT_ELEM_CHANGE (0.12): the master has modified data element or read/write.
    pub int_elem_change: bool,
    /// INT_END_WRBUF (0.13): end of write buffer reached.
    pub int_end_wrbuf: bool,
    /// INT_END_RDBUF (0.14): end of read buffer reached.
    pub int_end_rdbuf: bool,
    /// INT_END_MDT (0.15): the master reports end via END_MDT.
    pub int_end_mdt: bool,
    /// HS_MDT (1.0): handshake bit in MDT.
    pub hs_mdt: bool,
    /// L/S_MDT (1.1): read/write in MDT.
    #[doc(alias = "L/S_MDT")]
    pub ls_mdt: bool,
    /// END_MDT (1.2): end bit in MDT.
    pub end_mdt: bool,
    /// ELEM_MDT (1.5-3): data element in MDT.
    pub elem_mdt: u8,
    /// RECERR (1.7): the last transmission was erroneous.
    pub recerr: bool,
    /// NINFO_READ (1.9-8): number of info words in the read buffer.
    pub ninfo_read: NInfo,
    /// Words 2 and 3: buffer pointers.
    pub pointers: ScPointers,
    /// INT_SC_ERR (4.9): interrupt due to protocol error.
    pub int_sc_err: bool,
    /// The "(Not used)" bits of words 0–4 in place (masks [`ScSlave::RESERVED`]).
    pub reserved: [u16; 5],
}

impl ScSlave {
    /// "(Not used)" bits per word: 0.10-11; 1.6, 1.10-15; 4.0-8, 4.10-15.
    pub const RESERVED: [u16; 5] = [0x0C00, 0xFC40, 0, 0, 0xFDFF];

    /// Decodes the five control words (never fails).
    pub const fn from_words(words: [u16; 5]) -> Self {
        let [w0, w1, w2, w3, w4] = words;
        let r = Self::RESERVED;
        ScSlave {
            hs_at: bit(w0, 0),
            busy_at: bit(w0, 1),
            err_at: bit(w0, 2),
            cmd_at: bit(w0, 3),
            elem: field(w0, 4, 3) as u8,
            ls: bit(w0, 7),
            ninfo_write: NInfo::from_code(field(w0, 8, 2) as u8),
            int_elem_change: bit(w0, 12),
            int_end_wrbuf: bit(w0, 13),
            int_end_rdbuf: bit(w0, 14),
            int_end_mdt: bit(w0, 15),
            hs_mdt: bit(w1, 0),
            ls_mdt: bit(w1, 1),
            end_mdt: bit(w1, 2),
            elem_mdt: field(w1, 3, 3) as u8,
            recerr: bit(w1, 7),
            ninfo_read: NInfo::from_code(field(w1, 8, 2) as u8),
            pointers: ScPointers::from_words(w2, w3),
            int_sc_err: bit(w4, 9),
            reserved: [w0 & r[0], w1 & r[1], w2 & r[2], w3 & r[3], w4 & r[4]],
        }
    }

    /// Decodes the first five words of `words`.
    pub fn decode(words: &[u16]) -> Result<Self, RamError> {
        Ok(Self::from_words(take5(words)?))
    }

    /// Encodes the five control words (ELEM and ELEM_MDT are cut to 3 bits,
    /// `reserved` to the reserved bits).
    pub const fn to_words(self) -> [u16; 5] {
        let r = Self::RESERVED;
        let w0 = bool16(self.hs_at, 0)
            | bool16(self.busy_at, 1)
            | bool16(self.err_at, 2)
            | bool16(self.cmd_at, 3)
            | ((self.elem as u16) & 7) << 4
            | bool16(self.ls, 7)
            | (self.ninfo_write.code() as u16) << 8
            | bool16(self.int_elem_change, 12)
            | bool16(self.int_end_wrbuf, 13)
            | bool16(self.int_end_rdbuf, 14)
            | bool16(self.int_end_mdt, 15)
            | (self.reserved[0] & r[0]);
        let w1 = bool16(self.hs_mdt, 0)
            | bool16(self.ls_mdt, 1)
            | bool16(self.end_mdt, 2)
            | ((self.elem_mdt as u16) & 7) << 3
            | bool16(self.recerr, 7)
            | (self.ninfo_read.code() as u16) << 8
            | (self.reserved[1] & r[1]);
        let [w2, w3] = self.pointers.to_words();
        let w4 = bool16(self.int_sc_err, 9) | (self.reserved[4] & r[4]);
        [w0, w1, w2, w3, w4]
    }
}

/// A service container's control words in either mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServiceContainer {
    /// SCMASTER = 1.
    Master(ScMaster),
    /// SCMASTER = 0.
    Slave(ScSlave),
}

impl ServiceContainer {
    /// Decodes the five control words in the mode given by the data container's
    /// SCMASTER bit.
    pub const fn from_words(scmaster: bool, words: [u16; 5]) -> Self {
        if scmaster {
            ServiceContainer::Master(ScMaster::from_words(words))
        } else {
            ServiceContainer::Slave(ScSlave::from_words(words))
        }
    }

    /// Encodes the five control words.
    pub const fn to_words(self) -> [u16; 5] {
        match self {
            ServiceContainer::Master(m) => m.to_words(),
            ServiceContainer::Slave(s) => s.to_words(),
        }
    }

    /// The buffer pointers (words 2 and 3).
    pub const fn pointers(&self) -> ScPointers {
        match self {
            ServiceContainer::Master(m) => m.pointers,
            ServiceContainer::Slave(s) => s.pointers,
        }
    }
}
