//! Writes a run's trace files: telegram log, VCD, pcap, service-channel transcript.

use std::io::Write;
use std::path::Path;

use super::error::RingError;
use super::runner::RingOutcome;
use super::spec::TraceSpec;
use crate::transcript_json::EntryJson;

fn write(path: &Path, bytes: &[u8]) -> Result<(), RingError> {
    std::fs::write(path, bytes).map_err(|source| RingError::Write {
        path: path.display().to_string(),
        source,
    })
}

/// Writes every trace `spec` asks for from `outcome`.
pub fn write_traces(spec: &TraceSpec, outcome: &RingOutcome) -> Result<(), RingError> {
    if let Some(p) = &spec.log {
        write(p, &outcome.traces.log)?;
    }
    if let Some(p) = &spec.vcd {
        write(p, &outcome.traces.vcd)?;
    }
    if let Some(p) = &spec.pcap {
        write(p, &outcome.traces.capture)?;
    }
    if let Some(p) = &spec.transcript {
        let mut out = Vec::new();
        for e in &outcome.transcript {
            let line =
                serde_json::to_string(&EntryJson::from(e)).map_err(|e| RingError::Write {
                    path: p.display().to_string(),
                    source: std::io::Error::other(e),
                })?;
            let _ = writeln!(out, "{line}");
        }
        write(p, &out)?;
    }
    Ok(())
}
