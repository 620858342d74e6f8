//! Errors of the line layer.

/// A frame the decoder could not accept. Positions are absolute line bit indices; `start` is
/// the first bit of the opening flag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum LineError {
    /// The FCS received does not match the one computed over ADR and data
    /// (ERRATA, Telegrams: ISO/IEC 3309 FCS). The received bytes come with the error.
    #[error(
        "FCS mismatch in frame at bits {start}..{end}: received {received:04X}H, computed {computed:04X}H"
    )]
    FcsMismatch {
        /// First bit of the opening flag.
        start: u64,
        /// Bit after the closing flag.
        end: u64,
        /// FCS as received (low byte first on the line).
        received: u16,
        /// FCS computed over the received ADR and data.
        computed: u16,
    },
    /// Seven or more consecutive 1s inside a frame (HDLC abort; ERRATA, Telegrams: frame).
    #[error("frame opened at bit {start} aborted by seven 1s at bit {at}")]
    Abort {
        /// First bit of the opening flag.
        start: u64,
        /// Position of the seventh consecutive 1.
        at: u64,
    },
    /// Fewer bits between the flags than ADR and FCS ([`MIN_FRAME_BYTES`](super::MIN_FRAME_BYTES)).
    #[error("frame at bits {start}..{end} too short: {bits} bits between the flags")]
    TooShort {
        /// First bit of the opening flag.
        start: u64,
        /// Bit after the closing flag.
        end: u64,
        /// Bits between the flags after removing the inserted 0s.
        bits: u32,
    },
    /// The bits between the flags are not a whole number of bytes.
    #[error("frame at bits {start}..{end} holds {bits} bits, not a whole number of bytes")]
    NotWholeBytes {
        /// First bit of the opening flag.
        start: u64,
        /// Bit after the closing flag.
        end: u64,
        /// Bits between the flags after removing the inserted 0s.
        bits: u32,
    },
    /// More bytes between the flags than [`MAX_FRAME_BYTES`](super::MAX_FRAME_BYTES).
    #[error("frame opened at bit {start} longer than the limit at bit {at}")]
    TooLong {
        /// First bit of the opening flag.
        start: u64,
        /// Position where the limit was passed (the first bit of the closing flag when the
        /// frame ended just past the limit).
        at: u64,
    },
}

impl LineError {
    /// First bit of the opening flag of the frame in error.
    pub fn start(&self) -> u64 {
        match *self {
            LineError::FcsMismatch { start, .. }
            | LineError::Abort { start, .. }
            | LineError::TooShort { start, .. }
            | LineError::NotWholeBytes { start, .. }
            | LineError::TooLong { start, .. } => start,
        }
    }
}

/// Why the encoder refused a telegram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum EncodeError {
    /// No ADR byte: a telegram has at least its address (ERRATA, Telegrams: frame).
    #[error("empty telegram: at least the ADR byte is needed")]
    Empty,
    /// More telegram bytes than [`MAX_TELEGRAM_BYTES`](super::MAX_TELEGRAM_BYTES).
    #[error("telegram of {len} bytes longer than the limit of {max}")]
    TooLong {
        /// Telegram bytes given.
        len: usize,
        /// The limit.
        max: usize,
    },
    /// The output buffer had no room; nothing was written and the line level is unchanged.
    #[error(transparent)]
    SinkFull(#[from] super::bits::SinkFull),
}
