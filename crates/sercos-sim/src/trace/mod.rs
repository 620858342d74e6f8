//! Traces of what the simulated ring carried: a telegram log (text or JSON lines), pcap and
//! pcapng captures for Wireshark, and a hash of the trace for determinism checks.
//!
//! The simulator describes each telegram (or line error) it sees on a segment as a
//! [`TraceRecord`] and hands it to one or more [`TraceSink`]s:
//!
//! * [`TelegramLog`]: one line per record, as text or JSON ([`LogFormat`]);
//! * [`PcapTrace`] / [`PcapNgTrace`]: captures with link type USER0 (147) and the pseudo-header
//!   of [`link_header`], which `contrib/wireshark/sercos2.lua` dissects;
//! * [`TraceHasher`]: SHA-256 over the records in capture form, for "same seed, same trace"
//!   tests.
//!
//! Every writer formats deterministically: the same records give the same bytes.
//!
//! ```
//! use sercos_sim::trace::{LogFormat, SegmentId, TelegramLog, TraceRecord, TraceSink};
//! use sercos_wire::telegram::Origin;
//! use sercos_wire::time::Instant;
//!
//! let mut log = TelegramLog::new(Vec::new(), LogFormat::Text);
//! // An MST in phase 4: ADR 255, phase byte 04H (sercos-telegrams.md, MST).
//! log.record(&TraceRecord::telegram(Instant::ZERO, SegmentId(0), Origin::Master, &[0xFF, 0x04]))?;
//! let text = String::from_utf8(log.finish()?).expect("the log is text");
//! assert_eq!(text, "0.000000000000 seg 0 master MST adr 255 phase 4 byte 04H len 2 fcs ok\n");
//! # Ok::<(), sercos_sim::trace::TraceError>(())
//! ```

pub mod hash;
pub mod link_header;
pub mod pcap;
pub mod record;
pub mod summary;
pub mod telegram_log;

pub use hash::{TraceHash, TraceHasher};
pub use pcap::{PcapNgTrace, PcapTrace};
pub use record::{LineErrorKind, Seen, SegmentId, TraceRecord};
pub use summary::{Detail, FcsVerdict, Summary};
pub use telegram_log::{LogFormat, TelegramLog};

/// Why a trace could not be written.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    /// The output refused the bytes.
    #[error("trace output: {0}")]
    Io(#[from] std::io::Error),
    /// The pcap or pcapng writer failed.
    #[error("pcap writer: {0}")]
    Pcap(#[from] pcap_file::PcapError),
    /// A record too long for the capture format (more than `u32::MAX` bytes).
    #[error("record of {len} bytes too long for a capture")]
    TooLong {
        /// Bytes in the record.
        len: usize,
    },
}

/// Something that takes trace records: a log, a capture, a hasher, or several at once
/// (tuples of sinks feed each in turn).
pub trait TraceSink {
    /// Takes one record.
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError>;
}

impl<S: TraceSink + ?Sized> TraceSink for &mut S {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        (**self).record(record)
    }
}

impl<S: TraceSink + ?Sized> TraceSink for Box<S> {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        (**self).record(record)
    }
}

impl<A: TraceSink, B: TraceSink> TraceSink for (A, B) {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        self.0.record(record)?;
        self.1.record(record)
    }
}

impl<A: TraceSink, B: TraceSink, C: TraceSink> TraceSink for (A, B, C) {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        self.0.record(record)?;
        self.1.record(record)?;
        self.2.record(record)
    }
}
