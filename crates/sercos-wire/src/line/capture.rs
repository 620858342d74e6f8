//! The capture file format of `../shared/captures/` (its README): two bytes of telegram count,
//! big-endian, then the line signal, most significant bit of each byte first.

use super::bits::Bits;

/// A capture file too short to hold its header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("capture file of {len} bytes has no 2-byte telegram count")]
pub struct CaptureError {
    /// Length of the file in bytes.
    pub len: usize,
}

/// A parsed capture file: the header's telegram count and the line bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CaptureFile<'a> {
    /// Number of telegrams the file says it holds.
    pub telegram_count: u16,
    /// The line signal (NRZI in the captures we have).
    pub bits: Bits<'a>,
}

impl<'a> CaptureFile<'a> {
    /// Splits a capture file into its header and its bits.
    pub fn parse(file: &'a [u8]) -> Result<Self, CaptureError> {
        match file {
            [hi, lo, rest @ ..] => Ok(CaptureFile {
                telegram_count: u16::from_be_bytes([*hi, *lo]),
                bits: Bits::from_bytes(rest),
            }),
            _ => Err(CaptureError { len: file.len() }),
        }
    }
}
