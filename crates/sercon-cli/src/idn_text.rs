//! Human-readable text for service-channel transactions.

use sercos_wire::idn::Element;
use sercos_wire::service_transcript::{ServiceOp, TranscriptEntry};

/// One transcript entry as a line of text, e.g.
/// `phase 2  drive 1  write S-0-0001 operation data = 2000`.
pub fn transcript_line(e: &TranscriptEntry) -> String {
    let idn = e
        .idn
        .map(|i| i.to_string())
        .unwrap_or_else(|| "(no IDN open)".to_string());
    let head = format!("phase {}  drive {:>3}  ", e.phase, e.drive);
    let tail = if e.complete { "" } else { "  (broken off)" };
    match e.op {
        ServiceOp::Open => format!("{head}open  {idn}{tail}"),
        ServiceOp::Read => {
            let steps = if e.steps == 1 { "step" } else { "steps" };
            format!(
                "{head}read  {idn} {} ({} {steps}){tail}",
                e.element.name(),
                e.steps
            )
        }
        ServiceOp::Write => {
            let value = if e.element == Element::OperationData || e.words.len() == 1 {
                words_text(&e.words)
            } else {
                words_text(&e.words)
            };
            format!("{head}write {idn} {} = {value}{tail}", e.element.name())
        }
    }
}

fn words_text(words: &[u16]) -> String {
    match words {
        [w] => w.to_string(),
        _ => {
            let parts: Vec<String> = words.iter().map(|w| format!("{w:04X}H")).collect();
            format!("[{}]", parts.join(" "))
        }
    }
}
