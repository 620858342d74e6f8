//! `sercon idn read|write|list|info`: a drive's parameters (IDNs) through the master's
//! service channel on a simulated ring, in the manner of the EtherCAT master's `soe_read` /
//! `soe_write`. Values are decoded and parsed by the attribute the drive itself reports
//! (element 3; sercos-facts.md, IDNs, "Attribute (32 bit)"), with the drive's name (element
//! 2) and unit (element 4).
//!
//! Readings chosen: `docs/spec-notes.md`, "IDN tool".

mod session;
mod value_parse;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, Subcommand, ValueEnum};
use sercdrv::service_channel::{Request, Response};
use sercon_cli::ring::RingSpec;
use sercos_wire::attribute::{Attribute, DataLength, DisplayFormat, Value};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::telegram::CommunicationPhase;
use serde_json::json;

use crate::ring_shape::RingShape;

use crate::stdout_lines::say;
use session::{Session, TargetPhase};

/// `sercon idn …`.
#[derive(Debug, Subcommand)]
pub enum IdnCommand {
    /// Read one element of an IDN (default: its operation data), decoded by its attribute.
    Read(ReadArgs),
    /// Write the operation data of an IDN, the value parsed by the IDN's attribute.
    Write(WriteArgs),
    /// List every IDN of the drive (S-0-0017) with its name.
    List(ListArgs),
    /// Everything about one IDN: name, attribute decoded, unit, minimum, maximum, value.
    Info(InfoArgs),
}

/// The ring, the drive and the output, shared by every `sercon idn` subcommand.
#[derive(Debug, Args)]
pub struct RingOptions {
    /// The drive's SERCOS address.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=254))]
    drive: u8,
    /// The phase the ring is brought to before the access.
    #[arg(long, default_value = "4", value_parser = parse_phase)]
    phase: u8,
    #[command(flatten)]
    shape: RingShape,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// The data block elements a person asks for (sercos-facts.md, "Data block": elements 2-7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ElementArg {
    /// Element 2.
    Name,
    /// Element 3.
    Attribute,
    /// Element 4.
    Unit,
    /// Element 5.
    Min,
    /// Element 6.
    Max,
    /// Element 7, the operation data.
    Data,
}

impl ElementArg {
    fn element(self) -> Element {
        match self {
            ElementArg::Name => Element::Name,
            ElementArg::Attribute => Element::Attribute,
            ElementArg::Unit => Element::Unit,
            ElementArg::Min => Element::Minimum,
            ElementArg::Max => Element::Maximum,
            ElementArg::Data => Element::OperationData,
        }
    }
}

/// `sercon idn read`.
#[derive(Debug, Args)]
pub struct ReadArgs {
    #[command(flatten)]
    ring: RingOptions,
    /// The IDN, e.g. S-0-0036 or P-0-0019.
    #[arg(value_parser = parse_idn)]
    idn: Idn,
    /// The element read.
    #[arg(long, value_enum, default_value = "data")]
    element: ElementArg,
}

/// `sercon idn write`.
#[derive(Debug, Args)]
pub struct WriteArgs {
    #[command(flatten)]
    ring: RingOptions,
    /// The IDN, e.g. S-0-0036.
    #[arg(value_parser = parse_idn)]
    idn: Idn,
    /// The value, as the attribute shows it: 1500.0, -3, 0x1F, 0b101, text, or an IDN list
    /// such as [S-0-0011,S-0-0051].
    #[arg(allow_hyphen_values = true)]
    value: String,
}

/// `sercon idn list`.
#[derive(Debug, Args)]
pub struct ListArgs {
    #[command(flatten)]
    ring: RingOptions,
}

/// `sercon idn info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    #[command(flatten)]
    ring: RingOptions,
    /// The IDN, e.g. S-0-0036.
    #[arg(value_parser = parse_idn)]
    idn: Idn,
}

fn parse_idn(text: &str) -> Result<Idn, String> {
    text.parse::<Idn>()
        .map_err(|e| format!("{text:?} is not an IDN such as S-0-0036 or P-0-0019: {e}"))
}

fn parse_phase(text: &str) -> Result<u8, String> {
    match text {
        "2" => Ok(2),
        "4" => Ok(4),
        _ => Err(format!("{text:?} is not 2 or 4")),
    }
}

/// The ring of the config file (if any) with the options applied over it.
fn spec_of(o: &RingOptions) -> Result<RingSpec> {
    let mut spec = o.shape.spec()?;
    // A tool access needs neither faults nor traces nor a motion run.
    spec.faults.clear();
    spec.traces = Default::default();
    Ok(spec)
}

fn open(o: &RingOptions) -> Result<Session> {
    let spec = spec_of(o)?;
    let phase = if o.phase == 2 {
        TargetPhase::Two
    } else {
        TargetPhase::Four
    };
    Session::open(&spec, o.drive, phase)
}

/// Runs `sercon idn …`.
pub fn run(cmd: IdnCommand) -> Result<()> {
    match cmd {
        IdnCommand::Read(a) => read(a),
        IdnCommand::Write(a) => write(a),
        IdnCommand::List(a) => list(a),
        IdnCommand::Info(a) => info(a),
    }
}

/// The words of a request, or the drive's refusal as the error (one line: drive, IDN,
/// element, code and meaning, e.g. `drive 2, S-0-0080 operation data: 7007H operation data
/// above maximum`).
fn ask(s: &mut Session, request: Request) -> Result<Response> {
    s.request(request)?.map_err(|e| anyhow!(e))
}

/// Element 2 or 4, text (sercos-facts.md: name and unit are variable-length text).
fn text_of(s: &mut Session, idn: Idn, element: Element) -> Result<String> {
    let r = ask(s, Request::read(idn, element))?;
    Ok(decode_text(&r.words))
}

fn decode_text(words: &[u16]) -> String {
    let text = Attribute::new(DataLength::VariableBytes, DisplayFormat::Text);
    match text.decode(words) {
        Ok(Value::Text(bytes)) => String::from_utf8_lossy(&bytes).into_owned(),
        _ => String::new(),
    }
}

/// The attribute (element 3, two words).
fn attribute_of(s: &mut Session, idn: Idn) -> Result<Attribute> {
    let r = ask(s, Request::read(idn, Element::Attribute))?;
    match r.words.as_slice() {
        [lo, hi] => Ok(Attribute::from_words([*lo, *hi])),
        other => bail!("the attribute of {idn} has {} words, not 2", other.len()),
    }
}

/// `value unit` decoded by `attribute`; the raw words when they do not decode.
fn shown(attribute: Attribute, unit: &str, words: &[u16]) -> String {
    match attribute.decode(words) {
        Ok(v) => {
            let text = attribute.display(&v).to_string();
            if unit.is_empty() {
                text
            } else {
                format!("{text} {unit}")
            }
        }
        Err(e) => {
            let raw: Vec<String> = words.iter().map(|w| format!("{w:04X}H")).collect();
            format!("[{}] (not decodable: {e})", raw.join(" "))
        }
    }
}

fn read(a: ReadArgs) -> Result<()> {
    let mut s = open(&a.ring)?;
    let idn = a.idn;
    let element = a.element.element();
    // The value is decoded by the attribute read from the drive, not the catalogue.
    let name = text_of(&mut s, idn, Element::Name)?;
    let (shown_value, words) = match element {
        Element::Name | Element::Unit => {
            let r = ask(&mut s, Request::read(idn, element))?;
            (decode_text(&r.words), r.words)
        }
        Element::Attribute => {
            let attribute = attribute_of(&mut s, idn)?;
            (attribute_text(attribute), attribute.to_words().to_vec())
        }
        _ => {
            let attribute = attribute_of(&mut s, idn)?;
            let unit = text_of(&mut s, idn, Element::Unit)?;
            let r = ask(&mut s, Request::read(idn, element))?;
            (shown(attribute, &unit, &r.words), r.words)
        }
    };
    let what = if element == Element::OperationData {
        String::new()
    } else {
        format!(" {}", element.name())
    };
    if a.ring.json {
        let out = json!({
            "drive": a.ring.drive,
            "phase": s.phase(),
            "idn": idn.to_string(),
            "name": name,
            "element": element.name(),
            "value": shown_value,
            "words": words,
        });
        say!("{out}");
    } else {
        say!("{idn} {name}{what} = {shown_value}");
    }
    Ok(())
}

fn write(a: WriteArgs) -> Result<()> {
    let mut s = open(&a.ring)?;
    let idn = a.idn;
    let name = text_of(&mut s, idn, Element::Name)?;
    let attribute = attribute_of(&mut s, idn)?;
    let unit = text_of(&mut s, idn, Element::Unit)?;
    let words = value_parse::parse_words(attribute, &a.value)
        .with_context(|| format!("value for {idn} {name}"))?;
    // A refusal comes back as the drive's code and meaning (sercos-facts.md, "Service
    // channel errors"), e.g. 7007H operation data above maximum.
    ask(&mut s, Request::write_value(idn, words.clone()))?;
    let value = shown(attribute, &unit, &words);
    // Read back what the drive now holds: a command value in the cyclic MDT is overwritten
    // by the master's next telegram (sercos-telegrams.md, MDT), which the reader should see.
    let back = ask(&mut s, Request::read(idn, Element::OperationData))?;
    let read_back = shown(attribute, &unit, &back.words);
    if a.ring.json {
        let out = json!({
            "drive": a.ring.drive,
            "phase": s.phase(),
            "idn": idn.to_string(),
            "name": name,
            "written": value,
            "words": words,
            "read_back": read_back,
        });
        say!("{out}");
    } else if read_back == value {
        // Compared as shown: the maximum-length word of variable data is the drive's own.
        say!("{idn} {name} := {value}");
    } else {
        say!("{idn} {name} := {value} (the drive now reads {read_back})");
    }
    Ok(())
}

/// S-0-0017, IDN list of all operation data (sercos-facts.md).
const IDN_LIST_OF_ALL: Idn = Idn::from_raw(17);

fn list(a: ListArgs) -> Result<()> {
    let mut s = open(&a.ring)?;
    let r = ask(&mut s, Request::read_value(IDN_LIST_OF_ALL))?;
    let attribute = r.attribute.unwrap_or(Attribute::new(
        DataLength::VariableWords,
        DisplayFormat::Idn,
    ));
    let idns = match attribute.decode(&r.words) {
        Ok(Value::IdnList(list)) => list,
        Ok(_) => bail!("drive {}: S-0-0017 is not a list of IDNs", a.ring.drive),
        Err(e) => bail!("drive {}: S-0-0017 does not decode: {e}", a.ring.drive),
    };
    let mut rows = Vec::new();
    for idn in idns {
        // A name the drive refuses is shown empty rather than ending the list.
        let name = match s.request(Request::read(idn, Element::Name))? {
            Ok(r) => decode_text(&r.words),
            Err(e) => format!("({})", e.kind),
        };
        rows.push((idn, name));
    }
    if a.ring.json {
        let list: Vec<_> = rows
            .iter()
            .map(|(idn, name)| json!({"idn": idn.to_string(), "name": name}))
            .collect();
        let out = json!({"drive": a.ring.drive, "phase": s.phase(), "idns": list});
        say!("{out}");
    } else {
        for (idn, name) in rows {
            say!("{idn} {name}");
        }
    }
    Ok(())
}

fn length_text(length: DataLength) -> &'static str {
    match length {
        DataLength::Reserved => "reserved (0)",
        DataLength::TwoBytes => "2 bytes",
        DataLength::FourBytes => "4 bytes",
        DataLength::EightBytes => "8 bytes",
        DataLength::VariableBytes => "variable, 1-byte elements",
        DataLength::VariableWords => "variable, 2-byte elements",
        DataLength::VariableLongs => "variable, 4-byte elements",
        DataLength::VariableDoubleLongs => "variable, 8-byte elements",
    }
}

fn format_text(format: DisplayFormat) -> &'static str {
    match format {
        DisplayFormat::Binary => "binary",
        DisplayFormat::UnsignedDecimal => "unsigned decimal",
        DisplayFormat::SignedDecimal => "signed decimal",
        DisplayFormat::Hexadecimal => "hexadecimal",
        DisplayFormat::Text => "text",
        DisplayFormat::Idn => "IDN",
        DisplayFormat::Float => "floating point",
        DisplayFormat::Reserved => "reserved (7)",
    }
}

/// Write protection per phase (sercos-facts.md, attribute bits 30-28), e.g.
/// `phase 2 writable, phase 3 protected, phase 4 protected`.
fn protection_text(attribute: Attribute) -> String {
    [
        (2, CommunicationPhase::Phase2),
        (3, CommunicationPhase::Phase3),
        (4, CommunicationPhase::Phase4),
    ]
    .iter()
    .map(|&(n, p)| {
        let w = if attribute.write_protected_in(p) {
            "protected"
        } else {
            "writable"
        };
        format!("phase {n} {w}")
    })
    .collect::<Vec<_>>()
    .join(", ")
}

/// `00xxxxxxH: 4 bytes, signed decimal, 4 decimal places, …` (one line).
fn attribute_text(attribute: Attribute) -> String {
    let mut text = format!(
        "{:08X}H: {}, {}, {} decimal places, factor {}",
        attribute.raw(),
        length_text(attribute.data_length()),
        format_text(attribute.display_format()),
        attribute.decimal_places(),
        attribute.conversion_factor()
    );
    if attribute.is_procedure_command() {
        text.push_str(", procedure command");
    }
    text.push_str(", ");
    text.push_str(&protection_text(attribute));
    text
}

fn info(a: InfoArgs) -> Result<()> {
    let mut s = open(&a.ring)?;
    let idn = a.idn;
    let name = text_of(&mut s, idn, Element::Name)?;
    let attribute = attribute_of(&mut s, idn)?;
    let unit = text_of(&mut s, idn, Element::Unit)?;
    // Minimum and maximum are optional (the drive refuses them where it has none, e.g.
    // 5001H): shown as "none" with the drive's answer.
    let mut limit = |element: Element| -> Result<(Option<String>, Option<String>)> {
        Ok(match s.request(Request::read(idn, element))? {
            Ok(r) => (Some(shown(attribute, &unit, &r.words)), None),
            Err(e) => (None, Some(e.kind.to_string())),
        })
    };
    let (min, min_why) = limit(Element::Minimum)?;
    let (max, max_why) = limit(Element::Maximum)?;
    let value = ask(&mut s, Request::read(idn, Element::OperationData))?;
    let value = shown(attribute, &unit, &value.words);
    if a.ring.json {
        let out = json!({
            "drive": a.ring.drive,
            "phase": s.phase(),
            "idn": idn.to_string(),
            "name": name,
            "attribute": format!("{:08X}H", attribute.raw()),
            "length": length_text(attribute.data_length()),
            "format": format_text(attribute.display_format()),
            "decimal_places": attribute.decimal_places(),
            "conversion_factor": attribute.conversion_factor(),
            "procedure_command": attribute.is_procedure_command(),
            "write_protected": {
                "phase2": attribute.write_protected_in(CommunicationPhase::Phase2),
                "phase3": attribute.write_protected_in(CommunicationPhase::Phase3),
                "phase4": attribute.write_protected_in(CommunicationPhase::Phase4),
            },
            "unit": unit,
            "min": min,
            "max": max,
            "value": value,
        });
        say!("{out}");
        return Ok(());
    }
    let or_none = |v: Option<String>, why: Option<String>| {
        v.unwrap_or_else(|| format!("none ({})", why.unwrap_or_default()))
    };
    say!("{idn} {name}");
    say!("  attribute          {:08X}H", attribute.raw());
    say!(
        "  length             {}",
        length_text(attribute.data_length())
    );
    say!(
        "  format             {}",
        format_text(attribute.display_format())
    );
    say!("  decimal places     {}", attribute.decimal_places());
    say!("  conversion factor  {}", attribute.conversion_factor());
    say!(
        "  procedure command  {}",
        if attribute.is_procedure_command() {
            "yes"
        } else {
            "no"
        }
    );
    say!("  write protection   {}", protection_text(attribute));
    say!(
        "  unit               {}",
        if unit.is_empty() { "(none)" } else { &unit }
    );
    say!("  minimum            {}", or_none(min, min_why));
    say!("  maximum            {}", or_none(max, max_why));
    say!("  value              {value}");
    Ok(())
}
