//! Real data: the SERCOS II line captures in `../shared/captures/` (see its README).
//! Skipped, with a message, when that folder is absent.

use std::path::PathBuf;

use sercos_wire::line::{self, CaptureFile, Decoded, Decoder, LineConfig};

fn captures_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/captures");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: capture folder {} not found; the real-data check did not run",
            dir.display()
        );
        None
    }
}

/// Decodes one capture with the fast decoder; returns (telegrams, errors, header count).
fn decode_capture(name: &str, chunk_bits: usize) -> Option<(Vec<Vec<u8>>, usize, u16)> {
    let dir = captures_dir()?;
    let file = std::fs::read(dir.join(name)).expect("capture file readable");
    let capture = CaptureFile::parse(&file).expect("capture has a header");
    let mut decoder = Decoder::new(LineConfig::RESET);
    let mut telegrams = Vec::new();
    let mut errors = 0;
    let bits = capture.bits;
    let mut at = 0;
    while at < bits.len() {
        let to = (at + chunk_bits).min(bits.len());
        let chunk = bits.slice(at, to).expect("in range");
        decoder.push(chunk, |d| match d {
            Decoded::Telegram(f) => telegrams.push(f.bytes.to_vec()),
            Decoded::Error { .. } => errors += 1,
        });
        at = to;
    }
    Some((telegrams, errors, capture.telegram_count))
}

// Captures README: every telegram carries a valid ISO/IEC 3309 FCS and the count matches the
// header (8429 and 9632); ERRATA, Telegrams: frame and FCS.
#[test]
fn capture_1_every_telegram_has_a_valid_fcs_and_the_count_matches() {
    let Some((telegrams, errors, count)) = decode_capture("tc2000r-phaseup.nrzi", 1 << 20) else {
        return;
    };
    assert_eq!(count, 8429);
    assert_eq!(errors, 0);
    assert_eq!(telegrams.len(), usize::from(count));
}

#[test]
fn capture_2_every_telegram_has_a_valid_fcs_and_the_count_matches() {
    let Some((telegrams, errors, count)) = decode_capture("tc2000r-phaseup-2.nrzi", 1 << 20) else {
        return;
    };
    assert_eq!(count, 9632);
    assert_eq!(errors, 0);
    assert_eq!(telegrams.len(), usize::from(count));
}

// Captures README: MSTs have address 255 and one byte of phase, stepping 0..=4; the other
// telegrams are MDTs (ERRATA, Telegrams: MST = ADR 255, one data byte, bits 2–0 = phase).
#[test]
fn capture_mst_phases_step_from_0_to_4() {
    let Some((telegrams, _, _)) = decode_capture("tc2000r-phaseup.nrzi", 4093) else {
        return;
    };
    let mut phases: Vec<u8> = telegrams
        .iter()
        .filter(|t| t.len() == 2 && t.first() == Some(&255))
        .filter_map(|t| t.get(1).map(|p| p & 0x07))
        .collect();
    phases.dedup();
    assert_eq!(phases, vec![0, 1, 2, 3, 4]);
}

// The fast decoder and the bit-serial reference agree on real data, chunked oddly.
#[test]
fn capture_fast_and_reference_agree() {
    let Some(dir) = captures_dir() else {
        return;
    };
    let file = std::fs::read(dir.join("tc2000r-phaseup-2.nrzi")).expect("capture file readable");
    let capture = CaptureFile::parse(&file).expect("capture has a header");
    let reference = line::reference::decode_all(capture.bits, LineConfig::RESET);
    let mut fast = Vec::new();
    let mut decoder = Decoder::new(LineConfig::RESET);
    let mut at = 0;
    let mut step = 1;
    while at < capture.bits.len() {
        let to = (at + step).min(capture.bits.len());
        decoder.push(capture.bits.slice(at, to).expect("in range"), |d| {
            fast.push(d.to_owned())
        });
        at = to;
        step = step % 997 + 13;
    }
    assert_eq!(fast, reference);
}
