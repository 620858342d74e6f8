//! Faults as a user sees them, through the library (`sercon_cli::ring`): a broken fibre, a
//! drive without power, bit errors. Each run reaches phase 4 first; fault times count from
//! there. 8 Mbit/s: see `ring_cli.rs`.

use sercon_cli::ring::{self, RingEventKind, RingReport, RingSpec, RunResult};
use sercos_wire::time::{BitRate, Duration};

fn run(faults: &[&str], seconds_ms: u64) -> RingReport {
    let spec = RingSpec {
        bit_rate: BitRate::Mbit8,
        run_for: Duration::from_millis(seconds_ms),
        faults: faults.iter().map(|f| f.parse().expect("a fault")).collect(),
        ..RingSpec::default()
    };
    ring::run(&spec, &mut |_| {}).expect("the ring runs").report
}

fn events(r: &RingReport) -> Vec<(f64, RingEventKind)> {
    r.events.iter().map(|e| (e.t_s, e.kind.clone())).collect()
}

/// Drives whose MST counter rose between `t` and `until`.
fn lost_msts_between(r: &RingReport, t: f64, until: f64) -> Vec<u8> {
    let mut v: Vec<u8> = events(r)
        .into_iter()
        .filter_map(|(at, k)| match k {
            RingEventKind::LostMsts { drive } if at >= t && at < until => Some(drive),
            _ => None,
        })
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

// 410B §4.1 2H.13 FIBBR: a broken fibre into drive 3 leaves drive 3 the first node without
// light; drives 3 and 4 lose MSTs (410B §4.2 word 10 NMSTERR); the master falls back to phase
// 0 and, once repaired, brings the ring back to phase 4 on its own.
#[test]
fn break_names_the_first_dark_node_and_the_ring_comes_back() {
    let r = run(&["break:3@200ms..400ms"], 1600);
    let p4 = r.phase4_at_s.expect("phase 4");
    let ev = events(&r);
    let opens: Vec<&RingEventKind> = ev
        .iter()
        .filter(|(_, k)| matches!(k, RingEventKind::Open { .. }))
        .map(|(_, k)| k)
        .collect();
    assert_eq!(
        opens,
        vec![&RingEventKind::Open {
            first_dark: "drive 3".into()
        }],
        "{ev:?}"
    );
    let open_at = ev
        .iter()
        .find(|(_, k)| matches!(k, RingEventKind::Open { .. }))
        .map(|(t, _)| *t)
        .unwrap_or(0.0);
    assert!(
        (open_at - (p4 + 0.2)).abs() < 0.003,
        "opened at {open_at}, phase 4 at {p4}"
    );
    assert!(
        ev.iter()
            .any(|(t, k)| *k == RingEventKind::Closed && (*t - (p4 + 0.4)).abs() < 0.003)
    );
    // Downstream of the break only.
    assert_eq!(lost_msts_between(&r, p4 + 0.1, p4 + 0.4), vec![3, 4]);
    assert!(
        ev.iter()
            .any(|(_, k)| matches!(k, RingEventKind::MasterError { .. }))
    );
    // Back in phase 4 after the repair, by itself.
    assert!(r.restarts >= 1);
    assert_eq!(r.final_phase, 4);
    assert_eq!(r.result, RunResult::Phase4);
    for d in &r.drives {
        assert_eq!(d.phase, 4, "drive {}", d.address);
        assert!(d.shutdowns >= 1, "drive {} never left phase 4", d.address);
        assert!(
            ev.iter()
                .any(|(_, k)| *k == RingEventKind::Operating { drive: d.address }),
            "drive {} not back: {ev:?}",
            d.address
        );
    }
    let m3 = r
        .drives
        .iter()
        .find(|d| d.address == 3)
        .map_or(0, |d| d.mst_errors);
    let m1 = r
        .drives
        .iter()
        .find(|d| d.address == 1)
        .map_or(0, |d| d.mst_errors);
    assert!(m3 > m1 + 100, "drive 3 {m3} vs drive 1 {m1} MST errors");
}

// A drive without power: it and the drives after it drop out; those after it lose MSTs.
#[test]
fn power_off_reports_the_drive_and_who_lost_msts() {
    // Long enough for a whole new phase-up after the power returns.
    let r = run(&["power:2@200ms..300ms"], 1500);
    let p4 = r.phase4_at_s.expect("phase 4");
    let ev = events(&r);
    let off = ev
        .iter()
        .find(|(_, k)| *k == RingEventKind::PowerOff { drive: 2 });
    let on = ev
        .iter()
        .find(|(_, k)| *k == RingEventKind::PowerOn { drive: 2 });
    assert!(
        off.is_some_and(|(t, _)| (t - (p4 + 0.2)).abs() < 0.002),
        "{ev:?}"
    );
    assert!(
        on.is_some_and(|(t, _)| (t - (p4 + 0.3)).abs() < 0.002),
        "{ev:?}"
    );
    assert_eq!(lost_msts_between(&r, p4 + 0.1, p4 + 0.3), vec![3, 4]);
    // Drive 2 left phase 4 (power gone), drive 1 too (the master fell back), and drives 3
    // and 4 shut down on their own: MST missing twice (410B §4.1 4H.9 INT_MSTMIS).
    for a in [1u8, 2, 3, 4] {
        assert!(
            ev.iter()
                .any(|(_, k)| matches!(k, RingEventKind::ShutDown { drive, .. } if *drive == a)),
            "drive {a}: {ev:?}"
        );
    }
    assert!(
        ev.iter()
            .any(|(_, k)| matches!(k, RingEventKind::MasterError { .. }))
    );
    // After power returns the master brings every drive back to phase 4 by itself.
    assert_eq!(r.final_phase, 4);
    for d in &r.drives {
        assert_eq!(d.phase, 4, "drive {}", d.address);
    }
}

// Bit errors: the FCS (ERRATA, Telegrams: ISO/IEC 3309) rejects corrupted telegrams; the
// error counters rise and no drive ever applies a command value the master did not send.
#[test]
fn bit_errors_count_and_never_apply_a_corrupted_command() {
    let r = run(&["ber:1e-4"], 600);
    assert_eq!(r.result, RunResult::Phase4);
    let missed: u64 = r.drives.iter().map(|d| d.ats_missed + d.mdts_missed).sum();
    assert!(missed > 20, "error counters {missed}");
    for d in &r.drives {
        assert!(
            d.commands_applied > 300,
            "drive {} applied {}",
            d.address,
            d.commands_applied
        );
        assert_eq!(d.corrupted_commands, 0, "drive {}", d.address);
    }
}

// The comparison is not vacuous: a command the master never sent is caught.
#[test]
fn an_unsent_command_would_be_counted() {
    let spec = RingSpec {
        bit_rate: BitRate::Mbit8,
        run_for: Duration::from_millis(50),
        ..RingSpec::default()
    };
    let mut built = ring::build(&spec, Vec::new(), false).expect("ring");
    // Forget what the master may send to drive 1: every value it applies is then foreign.
    built.drives[0].borrow().sent.borrow_mut().clear();
    built.drives[0].borrow().sent.borrow_mut().insert(i128::MAX);
    let end = sercos_wire::time::Instant::ZERO.saturating_add(Duration::from_secs(1));
    built.sim.run_until(end).expect("runs");
    // The master alone does not command motion: nothing applied, nothing foreign.
    assert_eq!(built.drives[0].borrow().corrupted.len(), 0);
    let mut m = built.master.borrow_mut();
    let address = sercos_wire::address::DriveAddress::new(1).expect("address");
    m.master
        .set_command(address, sercos_wire::idn::Idn::from_raw(36), 1234)
        .expect("phase 4 by now");
    drop(m);
    let end = end.saturating_add(Duration::from_millis(5));
    built.sim.run_until(end).expect("runs");
    assert_eq!(
        built.drives[0]
            .borrow()
            .corrupted
            .iter()
            .map(|c| c.1)
            .collect::<Vec<_>>(),
        vec![1234]
    );
}

// Task mst3 (spec-notes "MST window in whole µs"): on an intact ring no drive counts an MST
// error (410B §4.2 word 10 NMSTERR) through phases 0–4, also at the switch from phase 2 to
// 3, where the phase byte's stuffed bits move the MST's end by one bit time. The defaults
// (16 Mbit/s, 1 ms) are the ring where it was seen.
#[test]
fn intact_ring_counts_no_mst_error_through_the_phase_up() {
    let spec = RingSpec {
        run_for: Duration::from_millis(50),
        ..RingSpec::default()
    };
    let r = ring::run(&spec, &mut |_| {}).expect("the ring runs").report;
    assert_eq!(r.result, RunResult::Phase4);
    assert!(!r.drives.is_empty());
    for d in &r.drives {
        assert_eq!(d.phase, 4, "drive {}", d.address);
        assert_eq!(d.mst_errors, 0, "drive {} NMSTERR", d.address);
    }
    assert_eq!(lost_msts_between(&r, 0.0, f64::MAX), Vec::<u8>::new());
}

// spec-notes "Repeater collisions": drive 3's MCLK 8 % slow from the start of phase 4 moves
// its AT into drive 4's at drive 4's output (410B §1: the own telegram cuts or shadows the
// one repeated), where the simulator's fast path cannot follow the chips
// (`SimStats::fast_path_collisions`). The ring is run again on the reference path, and the
// report is that run's and says so: the same report as asked for on the reference path.
#[test]
fn a_run_the_fast_path_cannot_follow_is_the_reference_path_s() {
    let spec = RingSpec {
        run_for: Duration::from_millis(20),
        faults: vec!["drift:3:-80000@0ms".parse().expect("a fault")],
        ..RingSpec::default()
    };
    let fast = ring::run(&spec, &mut |_| {}).expect("the ring runs").report;
    let n = fast
        .fast_path_collisions
        .expect("collisions on the fast path");
    assert!(n > 0);
    assert!(fast.to_text().contains("reference path's run"));
    let reference = RingSpec {
        reference: true,
        ..spec
    };
    let mut asked = ring::run(&reference, &mut |_| {})
        .expect("the ring runs")
        .report;
    assert_eq!(asked.fast_path_collisions, None);
    asked.fast_path_collisions = Some(n);
    assert_eq!(fast, asked);
    assert_eq!(fast.result, RunResult::Phase4);
}

// spec-notes "The ring command", faults on the reference path: a ring with a fibre break
// (410B §4.1 2H.13 FIBBR behind it) runs on the reference path from the start. On the fast
// path this ring counted 4 collisions it could not follow and ran again; now its report is
// the reference path's, without a count, and the same as asked for with `--reference`.
#[test]
fn a_ring_with_a_fault_other_than_drift_runs_on_the_reference_path() {
    let spec = RingSpec {
        run_for: Duration::from_millis(600),
        faults: vec!["break:2@200ms..300ms".parse().expect("a fault")],
        ..RingSpec::default()
    };
    let mut runs_on_reference = true;
    let report = ring::run(&spec, &mut |p| runs_on_reference &= p.reference)
        .expect("the ring runs")
        .report;
    assert!(runs_on_reference, "a progress line said the fast path");
    assert_eq!(report.fast_path_collisions, None);
    let asked = RingSpec {
        reference: true,
        ..spec
    };
    let reference = ring::run(&asked, &mut |_| {})
        .expect("the ring runs")
        .report;
    assert_eq!(report, reference);
    assert_eq!(report.result, RunResult::Phase4);
}
