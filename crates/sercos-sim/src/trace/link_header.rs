//! The pseudo-header in front of every telegram in a sercon capture (pcap / pcapng link type
//! USER0 = 147), version 1.
//!
//! A capture packet is this 24-byte header followed by the bytes seen: the telegram bytes
//! (ADR and message field, without flags and FCS; ERRATA, Telegrams: frame) or, for a frame
//! that broke off, the bytes received before the error. All multi-byte fields are little
//! endian, as SERCOS words are on the line (ERRATA, Telegrams: "16-bit words go low byte
//! first").
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 1 | version, 1 |
//! | 1 | 1 | header length in bytes, 24: the telegram starts here (readers skip unknown tails) |
//! | 2 | 2 | segment number |
//! | 4 | 1 | flags: bit 0 origin (0 master, 1 slave), bit 1 FCS ok, bit 2 FCS fields valid, bit 3 line error |
//! | 5 | 1 | line error: 0 none, 1 FCS mismatch, 2 abort, 3 too short, 4 not whole bytes, 5 too long |
//! | 6 | 2 | bit rate in Mbit/s (2, 4, 8, 16), 0 unknown |
//! | 8 | 2 | FCS as received |
//! | 10 | 2 | FCS computed over the telegram bytes |
//! | 12 | 4 | reserved, 0 |
//! | 16 | 8 | time in picoseconds (the capture timestamp, in nanoseconds, drops the rest) |
//!
//! `contrib/wireshark/sercos2.lua` dissects this layout; docs/spec-notes.md ("Traces")
//! repeats it.

use sercos_wire::telegram::Origin;
use sercos_wire::time::{BitRate, Instant};

use super::record::{LineErrorKind, SegmentId, TraceRecord};

/// The version this module writes.
pub const VERSION: u8 = 1;
/// Bytes in the version-1 header.
pub const HEADER_LEN: usize = 24;
/// The pcap link type: LINKTYPE_USER0.
pub const LINKTYPE_USER0: u16 = 147;

/// Flag bit 0: sent by a slave (AT); clear: by the master (MST, MDT).
pub const FLAG_SLAVE: u8 = 1 << 0;
/// Flag bit 1: the FCS matched.
pub const FLAG_FCS_OK: u8 = 1 << 1;
/// Flag bit 2: the two FCS fields hold the received and the computed FCS.
pub const FLAG_FCS_VALID: u8 = 1 << 2;
/// Flag bit 3: the frame was in error; byte 5 says how.
pub const FLAG_LINE_ERROR: u8 = 1 << 3;

/// Field offsets.
mod field {
    pub(super) const VERSION: usize = 0;
    pub(super) const HEADER_LEN: usize = 1;
    pub(super) const SEGMENT: core::ops::Range<usize> = 2..4;
    pub(super) const FLAGS: usize = 4;
    pub(super) const LINE_ERROR: usize = 5;
    pub(super) const BIT_RATE: core::ops::Range<usize> = 6..8;
    pub(super) const FCS_RECEIVED: core::ops::Range<usize> = 8..10;
    pub(super) const FCS_COMPUTED: core::ops::Range<usize> = 10..12;
    pub(super) const TIME_PS: core::ops::Range<usize> = 16..24;
}

/// The header's values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinkHeader {
    /// Where the telegram was seen.
    pub segment: SegmentId,
    /// Who sent it.
    pub origin: Origin,
    /// Whether the FCS matched.
    pub fcs_ok: bool,
    /// FCS as received and as computed, when known.
    pub fcs: Option<(u16, u16)>,
    /// The line error, if any.
    pub line_error: Option<LineErrorKind>,
    /// The bit rate, when known.
    pub bit_rate: Option<BitRate>,
    /// When, in picoseconds.
    pub time: Instant,
}

/// Why bytes are not a version-1 header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum LinkHeaderError {
    /// Fewer bytes than the header needs.
    #[error("capture packet of {got} bytes shorter than the {needed}-byte header")]
    Truncated {
        /// Bytes needed.
        needed: usize,
        /// Bytes present.
        got: usize,
    },
    /// A version this reader does not know.
    #[error("pseudo-header version {0} not supported")]
    Version(u8),
    /// A line-error code outside 0–5.
    #[error("unknown line-error code {0}")]
    LineErrorCode(u8),
}

impl LinkHeader {
    /// The header for a record.
    pub fn of(record: &TraceRecord<'_>) -> LinkHeader {
        let line_error = record.line_error_kind();
        let fcs = record.fcs_pair();
        LinkHeader {
            segment: record.segment,
            origin: record.origin,
            fcs_ok: line_error.is_none(),
            fcs,
            line_error,
            bit_rate: record.bit_rate,
            time: record.time,
        }
    }

    /// The 24 header bytes.
    pub fn to_bytes(&self) -> [u8; HEADER_LEN] {
        let mut bytes = [0u8; HEADER_LEN];
        let mut flags = 0;
        if self.origin == Origin::Slave {
            flags |= FLAG_SLAVE;
        }
        if self.fcs_ok {
            flags |= FLAG_FCS_OK;
        }
        if self.fcs.is_some() {
            flags |= FLAG_FCS_VALID;
        }
        if self.line_error.is_some() {
            flags |= FLAG_LINE_ERROR;
        }
        let (received, computed) = self.fcs.unwrap_or((0, 0));
        let mbit = self.bit_rate.map_or(0, |rate| rate.mbit());
        put(&mut bytes, field::VERSION..field::VERSION + 1, &[VERSION]);
        put(
            &mut bytes,
            field::HEADER_LEN..field::HEADER_LEN + 1,
            &[HEADER_LEN as u8],
        );
        put(&mut bytes, field::SEGMENT, &self.segment.0.to_le_bytes());
        put(&mut bytes, field::FLAGS..field::FLAGS + 1, &[flags]);
        put(
            &mut bytes,
            field::LINE_ERROR..field::LINE_ERROR + 1,
            &[self.line_error.map_or(0, LineErrorKind::code)],
        );
        put(
            &mut bytes,
            field::BIT_RATE,
            &u16::try_from(mbit).unwrap_or(0).to_le_bytes(),
        );
        put(&mut bytes, field::FCS_RECEIVED, &received.to_le_bytes());
        put(&mut bytes, field::FCS_COMPUTED, &computed.to_le_bytes());
        put(
            &mut bytes,
            field::TIME_PS,
            &self.time.as_picos().to_le_bytes(),
        );
        bytes
    }

    /// Reads a header and returns it with the bytes after it (the header-length field says
    /// where they start).
    pub fn parse(packet: &[u8]) -> Result<(LinkHeader, &[u8]), LinkHeaderError> {
        let truncated = LinkHeaderError::Truncated {
            needed: HEADER_LEN,
            got: packet.len(),
        };
        let head = packet.get(..HEADER_LEN).ok_or(truncated)?;
        let byte = |at: usize| head.get(at).copied().unwrap_or(0);
        let version = byte(field::VERSION);
        if version != VERSION {
            return Err(LinkHeaderError::Version(version));
        }
        let len = usize::from(byte(field::HEADER_LEN)).max(HEADER_LEN);
        let payload = packet.get(len..).ok_or(LinkHeaderError::Truncated {
            needed: len,
            got: packet.len(),
        })?;
        let flags = byte(field::FLAGS);
        let code = byte(field::LINE_ERROR);
        let line_error = match code {
            0 => None,
            code => {
                Some(LineErrorKind::from_code(code).ok_or(LinkHeaderError::LineErrorCode(code))?)
            }
        };
        let mbit = u16_at(head, field::BIT_RATE);
        let header = LinkHeader {
            segment: SegmentId(u16_at(head, field::SEGMENT)),
            origin: if flags & FLAG_SLAVE != 0 {
                Origin::Slave
            } else {
                Origin::Master
            },
            fcs_ok: flags & FLAG_FCS_OK != 0,
            fcs: (flags & FLAG_FCS_VALID != 0).then(|| {
                (
                    u16_at(head, field::FCS_RECEIVED),
                    u16_at(head, field::FCS_COMPUTED),
                )
            }),
            line_error,
            bit_rate: BitRate::from_mbit(u32::from(mbit)),
            time: Instant::from_picos(u64_at(head, field::TIME_PS)),
        };
        Ok((header, payload))
    }
}

/// Copies `value` into `bytes[range]` (ranges are the constants above, inside the header).
fn put(bytes: &mut [u8; HEADER_LEN], range: core::ops::Range<usize>, value: &[u8]) {
    if let Some(target) = bytes.get_mut(range) {
        if target.len() == value.len() {
            target.copy_from_slice(value);
        }
    }
}

fn u16_at(bytes: &[u8], range: core::ops::Range<usize>) -> u16 {
    match bytes.get(range) {
        Some(&[low, high]) => u16::from_le_bytes([low, high]),
        _ => 0,
    }
}

fn u64_at(bytes: &[u8], range: core::ops::Range<usize>) -> u64 {
    bytes
        .get(range)
        .and_then(|slice| <[u8; 8]>::try_from(slice).ok())
        .map_or(0, u64::from_le_bytes)
}
