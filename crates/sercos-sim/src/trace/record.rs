//! What the simulator reports for each frame seen on a segment.

use core::fmt;

use sercos_wire::line::{Decoded, LineError, fcs};
use sercos_wire::telegram::Origin;
use sercos_wire::time::{BitRate, Instant};

/// A segment of the ring: one fibre (or the RS-485 bus) between two stations, numbered by the
/// simulator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SegmentId(pub u16);

impl fmt::Display for SegmentId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

/// The kinds of [`LineError`], without their positions, with the codes the capture
/// pseudo-header uses ([`link_header`](super::link_header)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LineErrorKind {
    /// The received FCS does not match (ERRATA, Telegrams: ISO/IEC 3309 FCS).
    FcsMismatch,
    /// Seven or more 1s in a row inside the frame (HDLC abort; ERRATA, Telegrams: frame).
    Abort,
    /// Fewer bytes between the flags than ADR and FCS.
    TooShort,
    /// Not a whole number of bytes between the flags.
    NotWholeBytes,
    /// More bytes between the flags than the decoder's limit.
    TooLong,
}

impl LineErrorKind {
    /// All kinds, by code.
    pub const ALL: [LineErrorKind; 5] = [
        LineErrorKind::FcsMismatch,
        LineErrorKind::Abort,
        LineErrorKind::TooShort,
        LineErrorKind::NotWholeBytes,
        LineErrorKind::TooLong,
    ];

    /// The kind of a decoder error.
    pub fn of(error: &LineError) -> LineErrorKind {
        match error {
            LineError::FcsMismatch { .. } => LineErrorKind::FcsMismatch,
            LineError::Abort { .. } => LineErrorKind::Abort,
            LineError::TooShort { .. } => LineErrorKind::TooShort,
            LineError::NotWholeBytes { .. } => LineErrorKind::NotWholeBytes,
            LineError::TooLong { .. } => LineErrorKind::TooLong,
        }
    }

    /// The code in the capture pseudo-header: 1–5 (0 there means "no line error").
    pub const fn code(self) -> u8 {
        match self {
            LineErrorKind::FcsMismatch => 1,
            LineErrorKind::Abort => 2,
            LineErrorKind::TooShort => 3,
            LineErrorKind::NotWholeBytes => 4,
            LineErrorKind::TooLong => 5,
        }
    }

    /// The kind with this code, if any.
    pub fn from_code(code: u8) -> Option<LineErrorKind> {
        LineErrorKind::ALL
            .into_iter()
            .find(|kind| kind.code() == code)
    }

    /// The short name used in logs: `fcs-mismatch`, `abort`, `too-short`, `not-whole-bytes`,
    /// `too-long`.
    pub const fn name(self) -> &'static str {
        match self {
            LineErrorKind::FcsMismatch => "fcs-mismatch",
            LineErrorKind::Abort => "abort",
            LineErrorKind::TooShort => "too-short",
            LineErrorKind::NotWholeBytes => "not-whole-bytes",
            LineErrorKind::TooLong => "too-long",
        }
    }
}

impl fmt::Display for LineErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What was seen: a telegram with a good FCS, or a frame in error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Seen<'a> {
    /// Telegram bytes (ADR and message field, without FCS and flags) with a valid FCS.
    Telegram(&'a [u8]),
    /// A frame the line decoder rejected.
    LineError {
        /// What went wrong.
        error: LineError,
        /// What was received: for an FCS mismatch the telegram bytes without the FCS,
        /// otherwise the bytes received before the error (as [`Decoded::Error`]).
        received: &'a [u8],
    },
}

/// One frame seen on one segment at one instant.
///
/// `time` is whatever instant the simulator attaches; the ring simulator uses the first bit
/// of the opening flag on that segment (docs/spec-notes.md, "Traces").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TraceRecord<'a> {
    /// When, in simulated picoseconds.
    pub time: Instant,
    /// Where.
    pub segment: SegmentId,
    /// Who sent it: the master (MST, MDT) or a slave (AT).
    pub origin: Origin,
    /// The segment's bit rate, when the simulator knows it.
    pub bit_rate: Option<BitRate>,
    /// What.
    pub seen: Seen<'a>,
}

impl<'a> TraceRecord<'a> {
    /// A telegram with a valid FCS.
    pub fn telegram(
        time: Instant,
        segment: SegmentId,
        origin: Origin,
        bytes: &'a [u8],
    ) -> TraceRecord<'a> {
        TraceRecord {
            time,
            segment,
            origin,
            bit_rate: None,
            seen: Seen::Telegram(bytes),
        }
    }

    /// A frame in error.
    pub fn line_error(
        time: Instant,
        segment: SegmentId,
        origin: Origin,
        error: LineError,
        received: &'a [u8],
    ) -> TraceRecord<'a> {
        TraceRecord {
            time,
            segment,
            origin,
            bit_rate: None,
            seen: Seen::LineError { error, received },
        }
    }

    /// What the line decoder yielded.
    pub fn from_decoded(
        time: Instant,
        segment: SegmentId,
        origin: Origin,
        decoded: &Decoded<'a>,
    ) -> TraceRecord<'a> {
        match *decoded {
            Decoded::Telegram(frame) => TraceRecord::telegram(time, segment, origin, frame.bytes),
            Decoded::Error { error, received } => {
                TraceRecord::line_error(time, segment, origin, error, received)
            }
        }
    }

    /// The same record with the segment's bit rate.
    pub fn with_bit_rate(self, bit_rate: BitRate) -> TraceRecord<'a> {
        TraceRecord {
            bit_rate: Some(bit_rate),
            ..self
        }
    }

    /// The bytes carried: the telegram, or what was received of the frame in error.
    pub fn bytes(&self) -> &'a [u8] {
        match self.seen {
            Seen::Telegram(bytes) => bytes,
            Seen::LineError { received, .. } => received,
        }
    }

    /// The line error's kind, if the frame was in error.
    pub fn line_error_kind(&self) -> Option<LineErrorKind> {
        match &self.seen {
            Seen::Telegram(_) => None,
            Seen::LineError { error, .. } => Some(LineErrorKind::of(error)),
        }
    }

    /// The FCS as received and as computed over the telegram bytes, when both are known: for
    /// a good telegram both are the FCS of its bytes (ERRATA, Telegrams: ISO/IEC 3309), for
    /// an FCS mismatch the decoder's two values; `None` for other line errors.
    pub fn fcs_pair(&self) -> Option<(u16, u16)> {
        match self.seen {
            Seen::Telegram(bytes) => {
                let value = fcs(bytes);
                Some((value, value))
            }
            Seen::LineError {
                error:
                    LineError::FcsMismatch {
                        received, computed, ..
                    },
                ..
            } => Some((received, computed)),
            Seen::LineError { .. } => None,
        }
    }
}
