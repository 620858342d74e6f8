//! `sercon ring --telegram-type N` (S-0-0015, sercos-facts.md "0–6 standard, 7 configured")
//! and the refusal of a cycle too short for the drives before the phase-up starts.

mod cli_support;

use cli_support::sercon;
use std::time::{Duration, Instant};

// sercos-facts.md S-0-0015: standard type 3 (MDT S-0-0036, AT S-0-0051) reaches phase 4 and
// the report names the type every drive was given.
#[test]
fn standard_telegram_type_3_reaches_phase_4() {
    let o = sercon(&[
        "ring",
        "--baud",
        "8",
        "--drives",
        "2",
        "--seconds",
        "0.05",
        "--telegram-type",
        "3",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON report");
    assert_eq!(r["final_phase"], 4);
    let text = r.to_string();
    assert!(text.contains("\"telegram_type\":3"), "{text}");
    assert!(!text.contains("\"telegram_type\":7"), "{text}");
}

// sercos-facts.md S-0-0015: 0-7 only.
#[test]
fn telegram_type_8_is_refused_by_the_option() {
    let o = sercon(&["ring", "--telegram-type", "8"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--telegram-type"), "{err}");
    assert!(o.stdout.is_empty());
}

// Timing planner (sercdrv::timing::plan_cycle, spec-notes "Master DMA layout"): 254 drives with
// type 7 need 4348 µs at 16 Mbit/s, more than a 4 ms cycle: one line, at once.
#[test]
fn a_cycle_too_short_for_254_drives_is_said_at_once_in_one_line() {
    let started = Instant::now();
    let o = sercon(&["ring", "--drives", "254", "--cycle-us", "4000"]);
    assert!(!o.status.success());
    assert!(started.elapsed() < Duration::from_secs(60), "not at once");
    let err = String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(err.contains("cycle too short"), "{err}");
    assert!(err.contains("4348 µs"), "{err}");
    assert!(err.contains("--telegram-type 3"), "{err}");
    assert!(o.stdout.is_empty());
}
