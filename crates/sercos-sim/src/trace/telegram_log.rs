//! The telegram log: one line per record, as text or as JSON.
//!
//! **Text** (fields separated by single spaces, always in this order):
//!
//! ```text
//! <seconds with 12 decimals> seg <segment> <master|slave> <MST|MDT|AT|->
//!     [adr <ADR>] [<detail>] len <bytes> fcs <ok|bad rx XXXXH calc XXXXH|-> [error <kind>]
//! ```
//!
//! where `<detail>` is `phase <bits 2–0> byte <XX>H` for an MST, `cw <XXXX>H si <XXXX>H` for
//! an MDT (its record at offset 0), `sw <XXXX>H si <XXXX>H` for an AT, `malformed` for bytes
//! too short for their kind and `broken` for a frame that broke off (abort, length errors).
//!
//! **JSON lines**: one object per line with the keys, in this order, `t_ps`, `segment`,
//! `origin` (`"master"`/`"slave"`), `kind` (`"MST"`, `"MDT"`, `"AT"` or `null`), `adr`
//! (number or `null`), then `phase` and `phase_byte` (MST), `control_word` and `service_info`
//! (MDT), `status_word` and `service_info` (AT) or `"detail":"malformed"`/`"broken"`, then
//! `len`, `fcs` (`"ok"`, `"bad"` or `"none"`), `fcs_received` and `fcs_computed` when bad, and
//! `line_error` (a [`LineErrorKind`](super::LineErrorKind) name or `null`), and last `bytes`,
//! every byte seen as lowercase hex. Numbers are decimal integers.

use core::fmt::Write as _;
use std::io::Write;

use sercos_wire::telegram::Origin;

use super::record::TraceRecord;
use super::summary::{Detail, FcsVerdict, Summary};
use super::{TraceError, TraceSink};

/// Picoseconds in a second.
const PICOS_PER_SECOND: u64 = 1_000_000_000_000;

/// The two line formats of the log.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LogFormat {
    /// Human-readable text lines.
    Text,
    /// One JSON object per line.
    JsonLines,
}

/// Writes one log line per record to `W`.
#[derive(Debug)]
pub struct TelegramLog<W: Write> {
    out: W,
    format: LogFormat,
    line: String,
    lines: u64,
}

impl<W: Write> TelegramLog<W> {
    /// A log writing `format` lines to `out`.
    pub fn new(out: W, format: LogFormat) -> Self {
        TelegramLog {
            out,
            format,
            line: String::with_capacity(160),
            lines: 0,
        }
    }

    /// The format.
    pub fn format(&self) -> LogFormat {
        self.format
    }

    /// Lines written so far.
    pub fn lines(&self) -> u64 {
        self.lines
    }

    /// Flushes the output.
    pub fn flush(&mut self) -> Result<(), TraceError> {
        Ok(self.out.flush()?)
    }

    /// Flushes and returns the output.
    pub fn finish(mut self) -> Result<W, TraceError> {
        self.out.flush()?;
        Ok(self.out)
    }
}

impl<W: Write> TraceSink for TelegramLog<W> {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        self.line.clear();
        format_record(record, self.format, &mut self.line);
        self.out.write_all(self.line.as_bytes())?;
        self.lines += 1;
        Ok(())
    }
}

/// Appends the log line for `record`, newline included, to `out`.
pub fn format_record(record: &TraceRecord<'_>, format: LogFormat, out: &mut String) {
    let summary = Summary::of(record);
    // Writing into a String cannot fail.
    let _ = match format {
        LogFormat::Text => text(record, &summary, out),
        LogFormat::JsonLines => json(record, &summary, out),
    };
}

/// The origin's name.
fn origin_name(origin: Origin) -> &'static str {
    match origin {
        Origin::Master => "master",
        Origin::Slave => "slave",
    }
}

/// Fixed-point seconds with 12 decimals: every picosecond shows, and the text sorts by time
/// within one run.
fn seconds(out: &mut String, picos: u64) -> core::fmt::Result {
    write!(
        out,
        "{}.{:012}",
        picos / PICOS_PER_SECOND,
        picos % PICOS_PER_SECOND
    )
}

fn text(record: &TraceRecord<'_>, summary: &Summary, out: &mut String) -> core::fmt::Result {
    seconds(out, record.time.as_picos())?;
    write!(
        out,
        " seg {} {} ",
        record.segment,
        origin_name(record.origin)
    )?;
    match summary.kind {
        Some(kind) => write!(out, "{kind}")?,
        None => out.push('-'),
    }
    if let Some(adr) = summary.address {
        write!(out, " adr {adr}")?;
    }
    match summary.detail {
        // sercos-telegrams.md, MST: "The lower 3 bits designate the SERCOS phase".
        Detail::Mst { phase_byte } => {
            write!(out, " phase {} byte {phase_byte:02X}H", phase_byte & 0b111)?
        }
        Detail::Mdt {
            control_word,
            service_info,
        } => write!(
            out,
            " cw {:04X}H si {service_info:04X}H",
            control_word.raw()
        )?,
        Detail::At {
            status_word,
            service_info,
        } => write!(out, " sw {:04X}H si {service_info:04X}H", status_word.raw())?,
        Detail::Malformed => out.push_str(" malformed"),
        Detail::Broken => out.push_str(" broken"),
    }
    write!(out, " len {} fcs ", summary.len)?;
    match summary.fcs {
        FcsVerdict::Ok => out.push_str("ok"),
        FcsVerdict::Bad { received, computed } => {
            write!(out, "bad rx {received:04X}H calc {computed:04X}H")?
        }
        FcsVerdict::NotChecked => out.push('-'),
    }
    if let Some(kind) = summary.line_error {
        write!(out, " error {kind}")?;
    }
    out.push('\n');
    Ok(())
}

fn json(record: &TraceRecord<'_>, summary: &Summary, out: &mut String) -> core::fmt::Result {
    write!(
        out,
        "{{\"t_ps\":{},\"segment\":{},\"origin\":\"{}\",\"kind\":",
        record.time.as_picos(),
        record.segment,
        origin_name(record.origin)
    )?;
    match summary.kind {
        Some(kind) => write!(out, "\"{kind}\"")?,
        None => out.push_str("null"),
    }
    out.push_str(",\"adr\":");
    match summary.address {
        Some(adr) => write!(out, "{adr}")?,
        None => out.push_str("null"),
    }
    match summary.detail {
        Detail::Mst { phase_byte } => write!(
            out,
            ",\"phase\":{},\"phase_byte\":{phase_byte}",
            phase_byte & 0b111
        )?,
        Detail::Mdt {
            control_word,
            service_info,
        } => write!(
            out,
            ",\"control_word\":{},\"service_info\":{service_info}",
            control_word.raw()
        )?,
        Detail::At {
            status_word,
            service_info,
        } => write!(
            out,
            ",\"status_word\":{},\"service_info\":{service_info}",
            status_word.raw()
        )?,
        Detail::Malformed => out.push_str(",\"detail\":\"malformed\""),
        Detail::Broken => out.push_str(",\"detail\":\"broken\""),
    }
    write!(out, ",\"len\":{},\"fcs\":", summary.len)?;
    match summary.fcs {
        FcsVerdict::Ok => out.push_str("\"ok\""),
        FcsVerdict::Bad { received, computed } => write!(
            out,
            "\"bad\",\"fcs_received\":{received},\"fcs_computed\":{computed}"
        )?,
        FcsVerdict::NotChecked => out.push_str("\"none\""),
    }
    out.push_str(",\"line_error\":");
    match summary.line_error {
        Some(kind) => write!(out, "\"{kind}\"")?,
        None => out.push_str("null"),
    }
    out.push_str(",\"bytes\":\"");
    for byte in record.bytes() {
        write!(out, "{byte:02x}")?;
    }
    out.push_str("\"}\n");
    Ok(())
}
