//! A fingerprint of a trace: SHA-256 over its records in capture form.
//!
//! DESIGN.md, Principles: "The same configuration and seed give byte-identical traces, on
//! every run." Comparing two [`TraceHash`]es checks that without keeping both traces.
//!
//! Each record is hashed as the capture packet [`PcapTrace`](super::PcapTrace) would write
//! (the 24-byte [`link_header`](super::link_header) followed by the bytes seen), preceded by
//! its length as a 32-bit little-endian number. Unlike the text log this covers everything
//! of a record: the exact picosecond time, the bit rate, both FCS values and every data byte.

use core::fmt;

use sha2::{Digest, Sha256};

use super::link_header::{HEADER_LEN, LinkHeader};
use super::record::TraceRecord;
use super::{TraceError, TraceSink};

/// A SHA-256 digest of a trace; shown as 64 lowercase hex digits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TraceHash(pub [u8; 32]);

impl TraceHash {
    /// The SHA-256 of `bytes` (for instance a file written earlier).
    pub fn of_bytes(bytes: &[u8]) -> TraceHash {
        TraceHash(Sha256::digest(bytes).into())
    }
}

impl fmt::Display for TraceHash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.iter().try_for_each(|byte| write!(f, "{byte:02x}"))
    }
}

/// A sink that hashes the records it sees (see the [module documentation](self)).
#[derive(Debug, Clone, Default)]
pub struct TraceHasher {
    digest: Sha256,
    records: u64,
}

impl TraceHasher {
    /// A hasher that has seen nothing.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records hashed so far.
    pub fn records(&self) -> u64 {
        self.records
    }

    /// The hash of everything seen so far; the hasher goes on.
    pub fn hash(&self) -> TraceHash {
        TraceHash(self.digest.clone().finalize().into())
    }

    /// The hash of everything seen.
    pub fn finish(self) -> TraceHash {
        TraceHash(self.digest.finalize().into())
    }
}

impl TraceSink for TraceHasher {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        let bytes = record.bytes();
        let len = HEADER_LEN.saturating_add(bytes.len());
        let len = u32::try_from(len).map_err(|_| TraceError::TooLong { len })?;
        self.digest.update(len.to_le_bytes());
        self.digest.update(LinkHeader::of(record).to_bytes());
        self.digest.update(bytes);
        self.records += 1;
        Ok(())
    }
}
