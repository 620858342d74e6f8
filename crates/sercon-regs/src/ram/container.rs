//! Data containers (410B §4.2.2).
//!
//! A telegram header is followed directly by its data containers, one after another,
//! until the container with LASTDC = 1 (ERRATA "data containers"). A receive container
//! has two control words (LEN/flags, POS), a transmit container one (LEN/flags); then
//! LEN data words (single buffer), 2 × LEN (double buffer: buffer 0 then buffer 1), or
//! none (DMA) (ERRATA "container words").

use crate::bitfield::{bit, field};
use crate::error::{FieldError, RamError};
use crate::ram::header::Buffering;

/// Control word 0 of a data container, shared by receive and transmit containers
/// (410B §4.2.2). All 16 bits are used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ContainerControl {
    /// LEN (bits 9-0): number of 16-bit data words of the data block.
    pub len: u16,
    /// SVFL (bit 10): the data block uses a service container.
    pub svfl: bool,
    /// NSV (bits 13-11): number of the service container used (0–7).
    pub nsv: u8,
    /// SCMASTER (bit 14): service container processed in master (1) or slave (0) mode.
    pub scmaster: bool,
    /// LASTDC (bit 15): last data container of the telegram.
    pub lastdc: bool,
}

impl ContainerControl {
    /// Width of LEN in bits (on both variants: bit 10 is SVFL).
    pub const LEN_BITS: u8 = 10;

    /// A control word with range-checked LEN (0–1023) and NSV (0–7).
    pub const fn new(
        len: u16,
        svfl: bool,
        nsv: u8,
        scmaster: bool,
        lastdc: bool,
    ) -> Result<Self, FieldError> {
        if let Err(e) = FieldError::check("LEN", len, Self::LEN_BITS) {
            return Err(e);
        }
        if let Err(e) = FieldError::check("NSV", nsv as u16, 3) {
            return Err(e);
        }
        Ok(ContainerControl {
            len,
            svfl,
            nsv,
            scmaster,
            lastdc,
        })
    }

    /// Decodes control word 0 (never fails: every bit pattern is a valid word).
    pub const fn from_word(word: u16) -> Self {
        // 410B §4.2.2: LEN 9-0, SVFL 10, NSV 13-11, SCMASTER 14, LASTDC 15.
        ContainerControl {
            len: field(word, 0, 10),
            svfl: bit(word, 10),
            nsv: field(word, 11, 3) as u8,
            scmaster: bit(word, 14),
            lastdc: bit(word, 15),
        }
    }

    /// Encodes control word 0 (LEN and NSV are cut to their widths).
    pub const fn to_word(self) -> u16 {
        (self.len & 0x03FF)
            | (self.svfl as u16) << 10
            | ((self.nsv as u16) & 7) << 11
            | (self.scmaster as u16) << 14
            | (self.lastdc as u16) << 15
    }

    /// Data words that follow the control words with the telegram's `buffering`.
    pub const fn data_words(self, buffering: Buffering) -> u32 {
        buffering.data_words(self.len)
    }
}

/// A receive data container's two control words (410B §4.2.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct RxContainer {
    /// Control word 0.
    pub control: ContainerControl,
    /// POS (word 1): position of the data block within the telegram in words; the
    /// first data record of a telegram has POS = 0.
    pub pos: u16,
}

impl RxContainer {
    /// Number of control words.
    pub const CONTROL_WORDS: usize = 2;

    /// Decodes the two control words.
    pub const fn from_words(words: [u16; 2]) -> Self {
        RxContainer {
            control: ContainerControl::from_word(words[0]),
            pos: words[1],
        }
    }

    /// Decodes the first two words of `words`.
    pub fn decode(words: &[u16]) -> Result<Self, RamError> {
        match words {
            [w0, w1, ..] => Ok(Self::from_words([*w0, *w1])),
            _ => Err(RamError::TooShort {
                needed: 2,
                got: words.len(),
            }),
        }
    }

    /// Encodes the two control words.
    pub const fn to_words(self) -> [u16; 2] {
        [self.control.to_word(), self.pos]
    }

    /// Total words of the container (control words and data) with `buffering`.
    pub const fn total_words(self, buffering: Buffering) -> u32 {
        Self::CONTROL_WORDS as u32 + self.control.data_words(buffering)
    }
}

/// A transmit data container's single control word (410B §4.2.2: POS only in case of
/// receive telegrams).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct TxContainer {
    /// Control word 0.
    pub control: ContainerControl,
}

impl TxContainer {
    /// Number of control words.
    pub const CONTROL_WORDS: usize = 1;

    /// Decodes the control word.
    pub const fn from_words(words: [u16; 1]) -> Self {
        TxContainer {
            control: ContainerControl::from_word(words[0]),
        }
    }

    /// Decodes the first word of `words`.
    pub fn decode(words: &[u16]) -> Result<Self, RamError> {
        match words.first() {
            Some(w) => Ok(Self::from_words([*w])),
            None => Err(RamError::TooShort { needed: 1, got: 0 }),
        }
    }

    /// Encodes the control word.
    pub const fn to_words(self) -> [u16; 1] {
        [self.control.to_word()]
    }

    /// Total words of the container (control word and data) with `buffering`.
    pub const fn total_words(self, buffering: Buffering) -> u32 {
        Self::CONTROL_WORDS as u32 + self.control.data_words(buffering)
    }
}
