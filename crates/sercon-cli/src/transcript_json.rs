//! The JSON-lines schema of the master's service-channel transcript: one object per entry of
//! [`sercos_wire::service_transcript::TranscriptEntry`], written by
//! `sercon capture transcript --json` and by `sercon ring --transcript`.

use sercos_wire::service_transcript::{ServiceOp, TranscriptEntry};
use serde::Serialize;

/// One transcript entry as JSON: phase, drive, operation, IDN, data block element, the words
/// moved, the handshake steps it took, whether it completed, and the index of its first
/// telegram.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct EntryJson {
    /// Communication phase of the MST when the request started.
    pub phase: u8,
    /// Drive address.
    pub drive: u8,
    /// `read`, `write` or `open`.
    pub op: &'static str,
    /// The IDN, when the transfer named one.
    pub idn: Option<String>,
    /// Data block element (sercos-telegrams.md, control word bits 5-3).
    pub element: u8,
    /// The words moved.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub words: Vec<u16>,
    /// Handshake steps.
    pub steps: u32,
    /// The transfer ended with its last-transmission step.
    pub complete: bool,
    /// Index of the transfer's first telegram among the master's telegrams.
    pub telegram: u64,
}

/// The name of a service-channel operation in the schema.
pub fn op_name(op: ServiceOp) -> &'static str {
    match op {
        ServiceOp::Read => "read",
        ServiceOp::Write => "write",
        ServiceOp::Open => "open",
    }
}

impl From<&TranscriptEntry> for EntryJson {
    fn from(e: &TranscriptEntry) -> EntryJson {
        EntryJson {
            phase: e.phase,
            drive: e.drive,
            op: op_name(e.op),
            idn: e.idn.map(|i| i.to_string()),
            element: e.element.bits(),
            words: e.words.clone(),
            steps: e.steps,
            complete: e.complete,
            telegram: e.first_telegram,
        }
    }
}
