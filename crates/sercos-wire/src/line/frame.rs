//! What the decoder yields.

use super::error::LineError;

/// A telegram received with a valid FCS.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame<'a> {
    /// First bit of the opening flag.
    pub start: u64,
    /// Bit after the closing flag.
    pub end: u64,
    /// Telegram bytes: ADR and data, FCS and flags stripped.
    pub bytes: &'a [u8],
}

/// One result of the decoder: a telegram, or an error with what was received of the frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Decoded<'a> {
    /// A telegram with a valid FCS.
    Telegram(Frame<'a>),
    /// A frame in error.
    Error {
        /// What went wrong, and where.
        error: LineError,
        /// What was received: for [`LineError::FcsMismatch`] the telegram bytes (ADR and data,
        /// the FCS stripped); otherwise the whole bytes received before the error.
        received: &'a [u8],
    },
}

impl Decoded<'_> {
    /// Whether this is a telegram with a valid FCS.
    pub fn fcs_ok(&self) -> bool {
        matches!(self, Decoded::Telegram(_))
    }

    /// First bit of the opening flag.
    pub fn start(&self) -> u64 {
        match self {
            Decoded::Telegram(f) => f.start,
            Decoded::Error { error, .. } => error.start(),
        }
    }

    /// An owned copy.
    #[cfg(feature = "alloc")]
    pub fn to_owned(&self) -> OwnedDecoded {
        match *self {
            Decoded::Telegram(f) => OwnedDecoded::Telegram {
                start: f.start,
                end: f.end,
                bytes: f.bytes.to_vec(),
            },
            Decoded::Error { error, received } => OwnedDecoded::Error {
                error,
                received: received.to_vec(),
            },
        }
    }
}

/// An owned [`Decoded`] (with the `alloc` feature).
#[cfg(feature = "alloc")]
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum OwnedDecoded {
    /// A telegram with a valid FCS.
    Telegram {
        /// First bit of the opening flag.
        start: u64,
        /// Bit after the closing flag.
        end: u64,
        /// Telegram bytes: ADR and data.
        bytes: alloc::vec::Vec<u8>,
    },
    /// A frame in error.
    Error {
        /// What went wrong, and where.
        error: LineError,
        /// What was received (see [`Decoded::Error`]).
        received: alloc::vec::Vec<u8>,
    },
}

#[cfg(feature = "alloc")]
impl OwnedDecoded {
    /// Whether this is a telegram with a valid FCS.
    pub fn fcs_ok(&self) -> bool {
        matches!(self, OwnedDecoded::Telegram { .. })
    }
}
