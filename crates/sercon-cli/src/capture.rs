//! `sercon capture`: decode real SERCOS II line captures (the format of
//! `../shared/captures/README.md`: a 2-byte big-endian telegram count, then the line signal
//! one bit per bit time, most significant bit first).

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::{Args, Subcommand, ValueEnum};
use sercos_wire::line::{self, CaptureFile, Coding, LineConfig, OwnedDecoded, Polarity};
use sercos_wire::service_transcript::TranscriptBuilder;
use sercos_wire::telegram::{
    AtPacket, ControlWord, MdtPacket, MstPacket, Origin, TelegramKind, classify,
};
use serde::Serialize;

use crate::idn_text;
use sercon_cli::transcript_json::EntryJson;

/// Subcommands of `sercon capture`.
#[derive(Debug, Subcommand)]
pub enum CaptureCommand {
    /// Decode every telegram of a capture file: index, bit offset, kind, address, phase or
    /// control word, service info, data, FCS verdict.
    Decode(DecodeArgs),
    /// Rebuild the master's service channel per drive from the capture's MDTs.
    Transcript(TranscriptArgs),
}

/// Which line coding the capture holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CodingArg {
    /// NRZI, 0 = change of level (the captures we have).
    Nrzi,
    /// NRZ.
    Nrz,
}

/// Options shared by the capture subcommands.
#[derive(Debug, Args)]
pub struct CaptureInput {
    /// The capture file.
    pub file: PathBuf,
    /// Line coding of the recorded signal.
    #[arg(long, value_enum, default_value_t = CodingArg::Nrzi)]
    pub coding: CodingArg,
    /// Decode even if the file's telegram count does not match what the signal holds.
    #[arg(long)]
    pub force: bool,
}

/// Arguments of `sercon capture decode`.
#[derive(Debug, Args)]
pub struct DecodeArgs {
    #[command(flatten)]
    input: CaptureInput,
    /// Who transmitted the recorded telegrams (decides MDT or AT for drive addresses).
    #[arg(long, value_enum, default_value_t = OriginArg::Master)]
    origin: OriginArg,
    /// One JSON object per line instead of text.
    #[arg(long)]
    json: bool,
}

/// Arguments of `sercon capture transcript`.
#[derive(Debug, Args)]
pub struct TranscriptArgs {
    #[command(flatten)]
    input: CaptureInput,
    /// One JSON object per line instead of text.
    #[arg(long)]
    json: bool,
}

/// Who sent the telegrams of a capture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OriginArg {
    /// The master's transmitter: MST and MDT.
    Master,
    /// A slave's transmitter: AT.
    Slave,
}

/// Runs a capture subcommand.
pub fn run(cmd: CaptureCommand) -> anyhow::Result<()> {
    match cmd {
        CaptureCommand::Decode(args) => decode(args),
        CaptureCommand::Transcript(args) => transcript(args),
    }
}

/// A capture read and decoded, checked against its header.
struct Loaded {
    frames: Vec<OwnedDecoded>,
}

fn load(input: &CaptureInput) -> anyhow::Result<Loaded> {
    let path = &input.file;
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let file = CaptureFile::parse(&bytes).with_context(|| describe(path))?;
    let coding = match input.coding {
        CodingArg::Nrzi => Coding::Nrzi,
        CodingArg::Nrz => Coding::Nrz,
    };
    // NRZI does not depend on the polarity; for NRZ the captures' convention is unknown, so
    // take the reset value (410B §4.1, 1H.7 POLRXD = 0).
    let frames = line::decode_all(file.bits, LineConfig::new(coding, Polarity::LightOnLow));
    let good = frames.iter().filter(|f| f.fcs_ok()).count();
    let declared = usize::from(file.telegram_count);
    if good != declared && !input.force {
        let bad = frames.len() - good;
        bail!(
            "{}: the header declares {declared} telegrams but the signal holds {good} with a valid FCS \
             ({bad} frames in error); the file is truncated, damaged or not a capture \
             (use --force to decode anyway)",
            path.display(),
        );
    }
    Ok(Loaded { frames })
}

fn describe(path: &Path) -> String {
    format!("{} is not a capture file", path.display())
}

/// One decoded telegram as JSON (`sercon capture decode --json`).
#[derive(Serialize)]
struct TelegramJson {
    index: usize,
    bit: u64,
    end_bit: Option<u64>,
    kind: &'static str,
    address: Option<u8>,
    #[serde(skip_serializing_if = "Option::is_none")]
    phase: Option<u8>,
    #[serde(skip_serializing_if = "Option::is_none")]
    control: Option<u16>,
    #[serde(skip_serializing_if = "Option::is_none")]
    status: Option<u16>,
    #[serde(skip_serializing_if = "Option::is_none")]
    service: Option<u16>,
    #[serde(skip_serializing_if = "Option::is_none")]
    data: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
    fcs_ok: bool,
}

fn hex(bytes: &[u8]) -> String {
    let mut s = String::with_capacity(bytes.len() * 3);
    for (i, b) in bytes.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        s.push_str(&format!("{b:02X}"));
    }
    s
}

/// The fields of one telegram, decoded as far as its bytes allow.
fn describe_telegram(index: usize, frame: &OwnedDecoded, origin: Origin) -> TelegramJson {
    let (bit, end_bit, bytes, error) = match frame {
        OwnedDecoded::Telegram { start, end, bytes } => {
            (*start, Some(*end), bytes.as_slice(), None)
        }
        OwnedDecoded::Error { error, received } => (
            error.start(),
            None,
            received.as_slice(),
            Some(error.to_string()),
        ),
    };
    let mut t = TelegramJson {
        index,
        bit,
        end_bit,
        kind: "?",
        address: bytes.first().copied(),
        phase: None,
        control: None,
        status: None,
        service: None,
        data: None,
        error,
        fcs_ok: frame.fcs_ok(),
    };
    match classify(bytes, origin) {
        Ok(TelegramKind::Mst) => {
            t.kind = "MST";
            if let Ok(p) = MstPacket::new_checked(bytes) {
                t.phase = Some(p.phase_bits());
            }
        }
        Ok(TelegramKind::Mdt) => {
            t.kind = "MDT";
            if let Ok(p) = MdtPacket::new_checked(bytes) {
                if bytes.first() == Some(&255) {
                    // sercos-telegrams.md: a broadcast MDT holds one record per drive at
                    // offsets only the master's S-0-0009 writes tell; show the message field.
                    t.data = Some(hex(p.message_field()));
                } else if let Ok(r) = p.record() {
                    t.control = Some(r.control_word().raw());
                    t.service = Some(r.service_info());
                    t.data = Some(hex(r.data_block()));
                }
            }
        }
        Ok(TelegramKind::At) => {
            t.kind = "AT";
            if let Ok(p) = AtPacket::new_checked(bytes) {
                t.status = Some(p.status_word().raw());
                t.service = Some(p.service_info());
                t.data = Some(hex(p.data_block()));
            }
        }
        Err(_) => {
            t.data = Some(hex(bytes));
        }
    }
    if t.error.is_some() && t.kind == "?" {
        t.kind = "error";
    }
    t
}

fn text_line(t: &TelegramJson) -> String {
    let mut s = format!(
        "#{:<6} bit {:<9} {:<5} {:>3}",
        t.index,
        t.bit,
        t.kind,
        t.address.map(|a| a.to_string()).unwrap_or_default()
    );
    if let Some(p) = t.phase {
        s.push_str(&format!("  phase {p}"));
    }
    if let Some(c) = t.control {
        s.push_str(&format!("  control {}", ControlWord::from_raw(c)));
    }
    if let Some(st) = t.status {
        s.push_str(&format!("  status {st:04X}H"));
    }
    if let Some(sv) = t.service {
        s.push_str(&format!("  service {sv:04X}H"));
    }
    if let Some(d) = &t.data {
        if !d.is_empty() {
            s.push_str(&format!("  data [{d}]"));
        }
    }
    s.push_str(if t.fcs_ok { "  FCS ok" } else { "  FCS BAD" });
    if let Some(e) = &t.error {
        s.push_str(&format!("  ({e})"));
    }
    s
}

fn decode(args: DecodeArgs) -> anyhow::Result<()> {
    let loaded = load(&args.input)?;
    let origin = match args.origin {
        OriginArg::Master => Origin::Master,
        OriginArg::Slave => Origin::Slave,
    };
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let mut phases: Vec<u8> = Vec::new();
    let (mut msts, mut mdts, mut ats, mut bad) = (0usize, 0usize, 0usize, 0usize);
    for (i, f) in loaded.frames.iter().enumerate() {
        let t = describe_telegram(i, f, origin);
        match t.kind {
            "MST" => msts += 1,
            "MDT" => mdts += 1,
            "AT" => ats += 1,
            _ => {}
        }
        if !t.fcs_ok {
            bad += 1;
        }
        if let Some(p) = t.phase {
            if phases.last() != Some(&p) {
                phases.push(p);
            }
        }
        let line = if args.json {
            serde_json::to_string(&t)?
        } else {
            text_line(&t)
        };
        if writeln!(out, "{line}").is_err() {
            // The reader went away (e.g. `| head`): stop quietly.
            return Ok(());
        }
    }
    if !args.json {
        let seq: Vec<String> = phases.iter().map(u8::to_string).collect();
        let _ = writeln!(
            out,
            "{} telegrams: {msts} MST, {mdts} MDT, {ats} AT; {} with a valid FCS, {bad} in error; phases {}",
            loaded.frames.len(),
            loaded.frames.len() - bad,
            seq.join(" → ")
        );
    }
    let _ = out.flush();
    Ok(())
}

fn transcript(args: TranscriptArgs) -> anyhow::Result<()> {
    let loaded = load(&args.input)?;
    let mut builder = TranscriptBuilder::new();
    for (i, f) in loaded.frames.iter().enumerate() {
        if let OwnedDecoded::Telegram { bytes, .. } = f {
            builder.master_telegram(bytes, i as u64);
        }
    }
    let entries = builder.finish();
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    for e in &entries {
        let line = if args.json {
            serde_json::to_string(&EntryJson::from(e))?
        } else {
            idn_text::transcript_line(e)
        };
        if writeln!(out, "{line}").is_err() {
            return Ok(());
        }
    }
    let _ = out.flush();
    Ok(())
}
