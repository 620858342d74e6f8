//! Human-readable text for service-channel transactions, with values decoded by the IDN's
//! meaning where the catalogue knows it (`sercos_wire::idn_catalog`).

use sercos_wire::idn::{Element, Idn};
use sercos_wire::idn_catalog;
use sercos_wire::service_transcript::{ServiceOp, TranscriptEntry};

/// One transcript entry as a line of text, e.g.
/// `phase 2  drive   1  write S-0-0002 communication cycle time = 2000 µs`.
pub fn transcript_line(e: &TranscriptEntry) -> String {
    let head = format!("phase {}  drive {:>3}  ", e.phase, e.drive);
    let tail = if e.complete { "" } else { "  (broken off)" };
    let idn = idn_label(e.idn);
    match e.op {
        ServiceOp::Open => format!("{head}open  {idn}{tail}"),
        ServiceOp::Read => {
            let steps = if e.steps == 1 { "step" } else { "steps" };
            format!(
                "{head}read  {idn}: {} ({} {steps}){tail}",
                e.element.name(),
                e.steps
            )
        }
        ServiceOp::Write => {
            let value = value_text(e.idn, e.element, &e.words);
            let what = if e.element == Element::OperationData {
                String::new()
            } else {
                format!(" {}", e.element.name())
            };
            format!("{head}write {idn}{what} = {value}{tail}")
        }
    }
}

/// `S-0-0002 communication cycle time`, or the bare IDN when the catalogue does not know it.
fn idn_label(idn: Option<Idn>) -> String {
    match idn {
        None => "(no IDN open)".to_string(),
        Some(i) => match idn_catalog::lookup(i) {
            Some(info) => format!("{i} {}", info.name),
            None => i.to_string(),
        },
    }
}

/// Words written, decoded by the IDN's attribute for operation data when known.
fn value_text(idn: Option<Idn>, element: Element, words: &[u16]) -> String {
    if element == Element::OperationData {
        if let Some(info) = idn.and_then(idn_catalog::lookup) {
            if let Ok(text) = info.display_words(words) {
                return text;
            }
        }
    }
    match words {
        [w] => w.to_string(),
        _ => {
            let parts: Vec<String> = words.iter().map(|w| format!("{w:04X}H")).collect();
            format!("[{}]", parts.join(" "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(idn: u16, words: &[u16]) -> TranscriptEntry {
        TranscriptEntry {
            phase: 2,
            drive: 1,
            op: ServiceOp::Write,
            idn: Some(Idn::from_raw(idn)),
            element: Element::OperationData,
            words: words.to_vec(),
            steps: words.len() as u32,
            complete: true,
            first_telegram: 0,
        }
    }

    #[test]
    fn values_are_decoded_by_meaning() {
        let line = transcript_line(&write(2, &[2000]));
        assert!(
            line.contains("S-0-0002") && line.ends_with("= 2000 µs"),
            "{line}"
        );
        // sercos-facts.md: variable-length data = current length, maximum length, data.
        let line = transcript_line(&write(0x10, &[6, 6, 11, 51, 0x8013]));
        assert!(
            line.contains("S-0-0011") && line.contains("P-0-0019"),
            "{line}"
        );
        // Unknown IDNs fall back to raw words.
        let line = transcript_line(&write(0x0FFF, &[1, 2]));
        assert!(line.ends_with("= [0001H 0002H]"), "{line}");
    }
}
