//! Phase 2 in parallel for rings with more drives than service containers: up to eight
//! drives' phase-2 work at once, one per service container (410B §4.2.4 SCPT0-7), the MDT
//! of each cycle addressed to one of them in turn (phases 1-2 carry one MDT record per
//! cycle, spec-notes "Driver master", parallel phase 2). The ring reaches phase 4, its
//! phase 2 takes fewer cycles than one drive after the other, and every drive still gets
//! its whole phase-2 dialogue, complete and in the same order.

mod master_support;

use master_support::*;
use sercdrv::master::{MasterConfig, Progress};
use sercon_regs::Variant;
use sercos_wire::address::DriveAddress;

/// More drives than the eight service containers: lanes 0-3 hold two drives each.
const DRIVES: usize = 12;

/// (op, IDN, element, complete) of every transcript entry of `drive` in phase 2.
fn dialogue(lines: &[String], drive: u64) -> Vec<(String, String, u64, bool)> {
    lines
        .iter()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|v| v["phase"] == 2 && v["drive"].as_u64() == Some(drive))
        .map(|v| {
            (
                v["op"].as_str().unwrap_or("").to_string(),
                v["idn"].as_str().unwrap_or("").to_string(),
                v["element"].as_u64().unwrap_or(99),
                v["complete"].as_bool().unwrap_or(false),
            )
        })
        .collect()
}

/// Phase-2 cycles of a 12-drive ring (16 Mbit/s, 1 ms) and its master's transcript.
fn phase_up(parallel: bool) -> (u64, Vec<String>) {
    let drives: Vec<DriveAddress> = (1..=DRIVES)
        .filter_map(|a| u8::try_from(a).ok().and_then(DriveAddress::new))
        .collect();
    let mut cfg = MasterConfig::new(Variant::Sercon816, rate(16), 1000, drives);
    cfg.parallel_phase2 = parallel;
    let mut ring = ring(cfg, standard_drives(DRIVES), Vec::new());
    assert!(ring.run_to_phase(2, 400).is_some(), "no phase 2");
    let phase2 = ring.run_to_phase(3, 12_000);
    let status = ring.master.borrow().status();
    let Some(phase2) = phase2 else {
        panic!("parallel {parallel}: no phase 3: {status:#?}");
    };
    assert!(ring.run_to_phase(4, 2000).is_some(), "no phase 4");
    ring.run_cycles(10);
    let status = ring.master.borrow().status();
    assert_eq!(status.progress, Progress::Cyclic, "{status:#?}");
    assert_eq!(status.restarts, 0);
    (phase2, json_lines(&transcript(&ring.master_telegrams())))
}

// 410B §4.2.4: eight service containers serve eight drives at once; phases 1-2: one MDT
// per cycle, to the drive it addresses (spec-notes "Driver master").
#[test]
fn twelve_drives_reach_phase_4_with_a_shorter_phase_2_and_the_same_dialogue() {
    let (serial_cycles, serial) = phase_up(false);
    let (parallel_cycles, parallel) = phase_up(true);
    // Measured: one MDT per cycle bounds the gain (spec-notes); at least a fifth less.
    assert!(
        parallel_cycles * 5 < serial_cycles * 4,
        "parallel phase 2 {parallel_cycles} cycles, serial {serial_cycles}"
    );
    for drive in 1..=DRIVES as u64 {
        let ours = dialogue(&parallel, drive);
        let one_by_one = dialogue(&serial, drive);
        assert!(ours.len() >= 20, "drive {drive}: {ours:?}");
        assert!(
            ours.iter().all(|e| e.3),
            "drive {drive}: incomplete: {ours:?}"
        );
        assert_eq!(ours, one_by_one, "drive {drive}: dialogue differs");
    }
    // The drives' dialogues are interleaved: drive 2's first entry comes before drive 1's
    // fifth (one after the other: after drive 1's reads).
    let nth = |lines: &[String], drive: u64, n: usize| {
        lines
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                serde_json::from_str::<serde_json::Value>(l)
                    .is_ok_and(|v| v["phase"] == 2 && v["drive"].as_u64() == Some(drive))
            })
            .nth(n)
            .map(|(i, _)| i)
    };
    let p = (nth(&parallel, 2, 0), nth(&parallel, 1, 4));
    assert!(p.0.is_some() && p.0 < p.1, "{p:?}");
    let s = (nth(&serial, 2, 0), nth(&serial, 1, 4));
    assert!(s.1.is_some() && s.0 > s.1, "{s:?}");
}
