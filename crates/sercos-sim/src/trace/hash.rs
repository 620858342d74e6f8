//! A fingerprint of a trace: SHA-256 over its text log.
//!
//! DESIGN.md, Principles: "The same configuration and seed give byte-identical traces, on
//! every run." Comparing two [`TraceHash`]es checks that without keeping both traces.

use core::fmt;

use sha2::{Digest, Sha256};

use super::record::TraceRecord;
use super::telegram_log::{LogFormat, format_record};
use super::{TraceError, TraceSink};

/// A SHA-256 digest of a trace; shown as 64 lowercase hex digits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TraceHash(pub [u8; 32]);

impl TraceHash {
    /// The SHA-256 of `bytes` (for instance a log file written earlier).
    pub fn of_bytes(bytes: &[u8]) -> TraceHash {
        TraceHash(Sha256::digest(bytes).into())
    }
}

impl fmt::Display for TraceHash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.iter().try_for_each(|byte| write!(f, "{byte:02x}"))
    }
}

/// A sink that hashes the text log of the records it sees: the hash equals
/// [`TraceHash::of_bytes`] over the [`TelegramLog`](super::TelegramLog) text of the same
/// records.
#[derive(Debug, Clone, Default)]
pub struct TraceHasher {
    digest: Sha256,
    line: String,
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
        self.line.clear();
        format_record(record, LogFormat::Text, &mut self.line);
        self.digest.update(self.line.as_bytes());
        self.records += 1;
        Ok(())
    }
}
