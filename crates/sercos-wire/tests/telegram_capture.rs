//! Acceptance on real line data: every telegram of the two TC2000R captures
//! (`../shared/captures/`, see its README.md) classifies and parses as an MST or MDT, re-emits
//! to the same bytes, and shows the structure the README describes.
//!
//! Framing comes from the line module's decoder (ERRATA.md, Telegrams, "frame" and "FCS"). The
//! test says that it skipped when the captures folder is absent.

use std::path::PathBuf;

use sercos_wire::line::{self, CaptureFile, LineConfig, OwnedDecoded};
use sercos_wire::telegram::{CommunicationPhase, MdtRepr, Origin, TelegramRepr};

fn capture(name: &str) -> Option<Vec<u8>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/captures")
        .join(name);
    match std::fs::read(&path) {
        Ok(bytes) => Some(bytes),
        Err(_) => {
            eprintln!(
                "SKIPPED: {} not found (the shared captures folder is absent)",
                path.display()
            );
            None
        }
    }
}

/// Splits the capture into telegram bytes (ADR and data, FCS checked and removed) with the
/// line decoder (whose bit-serial reference twin is proven equal in `line_*` tests).
fn telegrams(file: &[u8]) -> (usize, Vec<Vec<u8>>) {
    let capture = CaptureFile::parse(file).expect("capture header");
    let found = line::decode_all(capture.bits, LineConfig::RESET)
        .into_iter()
        .filter_map(|d| match d {
            OwnedDecoded::Telegram { bytes, .. } => Some(bytes),
            OwnedDecoded::Error { .. } => None,
        })
        .collect();
    (usize::from(capture.telegram_count), found)
}

fn check(name: &str) {
    let Some(file) = capture(name) else { return };
    let (count, telegrams) = telegrams(&file);
    assert_eq!(telegrams.len(), count, "{name}: telegrams with a good FCS");

    let mut phase = CommunicationPhase::Phase0;
    let mut mst_count = 0;
    let mut single = 0;
    let mut broadcast = 0;
    for bytes in &telegrams {
        // Only the master's line was recorded (captures README).
        let repr = TelegramRepr::parse_bytes(bytes, Origin::Master)
            .unwrap_or_else(|e| panic!("{name}: {bytes:02X?}: {e}"));
        assert_eq!(&repr.to_vec(), bytes, "{name}: re-emitted bytes differ");
        match repr {
            TelegramRepr::Mst(mst) => {
                mst_count += 1;
                // Captures README: "the phase steps 0, 1, 2, 3, 4".
                let now = mst.phase().expect("phases 0-4 only");
                assert_eq!(
                    mst.other_bits(),
                    0,
                    "{name}: MST byte {:02X}",
                    mst.phase_byte()
                );
                assert!(
                    now >= phase,
                    "{name}: phase went back from {phase} to {now}"
                );
                phase = now;
            }
            TelegramRepr::Mdt(MdtRepr::Single { address, record }) => {
                single += 1;
                // Captures README: phases 1–2, one drive (1–4) per cycle, 4 data bytes.
                assert!(!phase.is_cyclic(), "{name}: single MDT in {phase}");
                assert!((1..=4).contains(&address.get()));
                assert!(record.data_block.is_empty());
            }
            TelegramRepr::Mdt(mdt @ MdtRepr::Broadcast { message_field }) => {
                broadcast += 1;
                // Captures README: phases 3–4, four records of 8 bytes (control word,
                // service info, 4 bytes of command value).
                assert!(phase.is_cyclic(), "{name}: broadcast MDT in {phase}");
                assert_eq!(message_field.len(), 32);
                for offset in [0, 8, 16, 24] {
                    let record = mdt.record_at(offset, 4).expect("in bounds");
                    assert_eq!(record.data_block.len(), 4);
                }
                assert!(mdt.record_at(25, 4).is_err());
            }
            TelegramRepr::At(_) => unreachable!("classified by Origin::Master"),
        }
    }
    assert_eq!(phase, CommunicationPhase::Phase4, "{name}: ends in phase 4");
    assert!(mst_count > 0 && single > 0 && broadcast > 0);
    assert_eq!(mst_count + single + broadcast, count);
    eprintln!("{name}: {mst_count} MST, {single} single MDT, {broadcast} broadcast MDT");
}

#[test]
fn capture_phaseup_parses() {
    check("tc2000r-phaseup.nrzi");
}

#[test]
fn capture_phaseup_2_parses() {
    check("tc2000r-phaseup-2.nrzi");
}
