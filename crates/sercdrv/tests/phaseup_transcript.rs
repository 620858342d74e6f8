//! The master's service channel compared with the captures' master: the simulated master's
//! MDTs and the two real captures (`../shared/captures/`) go through the same
//! `sercos_wire::service_transcript` builder and the JSON-lines schema of
//! `sercon capture transcript --json`; every drive must see the same IDNs written in the same
//! phases, in the same order.

mod master_support;

use master_support::*;
use sercdrv::master::{MasterConfig, Progress};

/// (phase, IDN) of every write to `drive`, from JSON lines of the transcript schema.
fn writes_of(lines: &[String], drive: u64) -> Vec<(u64, String)> {
    lines
        .iter()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|v| v["op"] == "write" && v["drive"].as_u64() == Some(drive))
        .map(|v| {
            (
                v["phase"].as_u64().unwrap_or(99),
                v["idn"].as_str().unwrap_or("").to_string(),
            )
        })
        .collect()
}

// captures README: the master brings drives 1-4 from phase 0 to 4 at 2 Mbit/s, 2 ms; phase 2
// writes the timing and telegram configuration, S-0-0099 and S-0-0127 (set, cancel), phase 3
// S-0-0128 (set, cancel) (`sercon capture transcript`, spec-notes "Driver master").
#[test]
fn writes_the_same_idns_in_the_same_phases_as_the_captures() {
    let Some(captures) = capture_transcripts() else {
        eprintln!("skipped: ../shared/captures/ not found");
        return;
    };
    let cfg = MasterConfig::capture_ring();
    let mut ring = ring(cfg, standard_drives(4), Vec::new());
    assert!(ring.run_to_phase(4, 3000).is_some());
    ring.run_cycles(20);
    assert_eq!(ring.master.borrow().progress(), Progress::Cyclic);
    let ours = json_lines(&transcript(&ring.master_telegrams()));
    for (name, capture) in &captures {
        let capture = json_lines(capture);
        for drive in 1..=4 {
            let theirs = writes_of(&capture, drive);
            assert!(theirs.len() >= 15, "{name}: drive {drive}: {theirs:?}");
            assert_eq!(
                writes_of(&ours, drive),
                theirs,
                "{name}: drive {drive} written differently"
            );
        }
    }
}

// The JSON lines carry the schema of `sercon capture transcript --json`.
#[test]
fn transcript_lines_have_the_cli_schema() {
    let cfg = MasterConfig::capture_ring();
    let mut ring = ring(cfg, standard_drives(4), Vec::new());
    assert!(ring.run_to_phase(3, 3000).is_some());
    let lines = json_lines(&transcript(&ring.master_telegrams()));
    assert!(!lines.is_empty());
    for l in &lines {
        let v: serde_json::Value = serde_json::from_str(l).expect("a JSON line");
        for key in [
            "phase", "drive", "op", "idn", "element", "steps", "complete", "telegram",
        ] {
            assert!(v.get(key).is_some(), "{key} missing in {l}");
        }
    }
}
