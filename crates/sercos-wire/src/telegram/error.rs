//! The errors of the telegram views and representations.

use crate::address::Address;

use super::TelegramKind;

/// Why telegram bytes could not be viewed, parsed or emitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum TelegramError {
    /// The buffer is shorter than the telegram or record needs.
    #[error("{what} needs at least {needed} bytes, got {got}")]
    Truncated {
        /// What was being read: `"MST"`, `"MDT"`, `"AT"`, `"data record"`.
        what: &'static str,
        /// The minimum length in bytes.
        needed: usize,
        /// The length found.
        got: usize,
    },
    /// An MST is exactly two bytes (ADR and phase); this one is longer.
    #[error("an MST is 2 bytes (ADR, phase), got {got}")]
    MstTooLong {
        /// The length found.
        got: usize,
    },
    /// The ADR byte is not allowed for this kind of telegram.
    #[error("{kind} cannot carry address {address}")]
    BadAddress {
        /// The telegram kind.
        kind: TelegramKind,
        /// The address found.
        address: Address,
    },
    /// A data record at `offset` with `len` bytes does not fit in the message field.
    #[error(
        "data record at offset {offset} with {len} bytes does not fit in a message field of {available} bytes"
    )]
    RecordOutOfBounds {
        /// Offset of the record, counted from the first byte after ADR.
        offset: usize,
        /// Length of the record (4 + data block length).
        len: usize,
        /// Length of the message field.
        available: usize,
    },
    /// The buffer to emit into has the wrong length.
    #[error("{what} needs a buffer of {needed} bytes, got {got}")]
    BufferLength {
        /// What was being emitted.
        what: &'static str,
        /// The length needed.
        needed: usize,
        /// The buffer's length.
        got: usize,
    },
    /// The communication phase bits (MST bits 2–0) hold 5, 6 or 7.
    #[error("MST phase bits hold {0}, but only phases 0-4 exist")]
    UnknownPhase(u8),
}

impl TelegramError {
    /// `Ok` when `got` bytes hold at least `needed`, else [`TelegramError::Truncated`] for
    /// `what`: the length check every view makes before it reads.
    pub fn check_at_least(what: &'static str, needed: usize, got: usize) -> Result<(), Self> {
        if got < needed {
            Err(TelegramError::Truncated { what, needed, got })
        } else {
            Ok(())
        }
    }
}
