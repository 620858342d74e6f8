//! The master's errors on the simulated ring, each naming drive, phase and IDN where they
//! apply: a drive that refuses a value, a drive that is missing, a procedure command that
//! fails, and a ring that breaks (fibre broken, drive powered off), after whose repair the
//! master is back in phase 4 by itself.

mod master_support;

use master_support::*;
use sercdrv::master::{MasterConfig, MasterError, MasterErrorKind, Progress};
use sercdrv::service_channel::ErrorKind;
use sercon_regs::Variant;
use sercos_sim::{Fault, FaultKind};
use sercos_wire::address::DriveAddress;
use sercos_wire::attribute::Value;
use sercos_wire::idn::Idn;
use sercos_wire::service_error::ServiceError;
use sercos_wire::time::{Duration, Instant};

fn drive(a: u8) -> Option<DriveAddress> {
    DriveAddress::new(a)
}

fn halted_with(ring: &mut Ring, max_cycles: u64) -> MasterError {
    assert_eq!(
        ring.run_to_phase(4, max_cycles),
        None,
        "must not reach phase 4"
    );
    let status = ring.master.borrow().status();
    assert_eq!(status.progress, Progress::Halted, "{status:#?}");
    status.last_error.expect("an error")
}

// sercos-facts.md "Service channel errors": 7007H, value above the maximum. A drive whose
// S-0-0002 allows at most 1000 µs refuses the 2000 µs cycle: the master stops in phase 2
// naming the drive and S-0-0002.
#[test]
fn a_drive_that_refuses_a_value() {
    let mut dbs = standard_drives(4);
    if let Some(db) = dbs.get_mut(1) {
        let mut p = db.get(Idn::from_raw(2)).expect("S-0-0002").clone();
        p.max = Some(Value::Unsigned(1000));
        db.insert(p);
    }
    let mut ring = ring(MasterConfig::capture_ring(), dbs, Vec::new());
    let error = halted_with(&mut ring, 3000);
    assert_eq!(error.drive, drive(2));
    assert_eq!(error.phase, 2);
    assert_eq!(error.idn, Some(Idn::from_raw(2)));
    assert_eq!(
        error.kind,
        MasterErrorKind::ServiceChannel(ErrorKind::Drive(ServiceError::OperationDataAboveMaximum))
    );
    let text = error.to_string();
    assert!(
        text.contains("drive 2") && text.contains("S-0-0002"),
        "{text}"
    );
}

// Phase 1: a configured drive that never answers is reported missing (spec-notes "Driver
// master": after `detect_rounds` rounds).
#[test]
fn a_configured_drive_that_is_missing() {
    // Five drives configured, four on the ring.
    let cfg = MasterConfig::new(
        Variant::Sercon816,
        rate(2),
        2000,
        (1..=5).filter_map(DriveAddress::new).collect(),
    );
    let mut ring = ring(cfg, standard_drives(4), Vec::new());
    let error = halted_with(&mut ring, 3000);
    assert_eq!(error.drive, drive(5));
    assert_eq!(error.phase, 1);
    assert_eq!(error.idn, None);
    assert_eq!(error.kind, MasterErrorKind::DriveMissing);
}

// sercos-facts.md "Procedure commands": status with the error bit. Drive 3 believes its line
// runs at 2 Mbit/s (P-0-0002) on a 16 Mbit/s ring, so its S-0-0127 finds that the MDT does not
// end before t3 and fails.
#[test]
fn a_procedure_command_that_fails() {
    let cfg = MasterConfig::new(
        Variant::Sercon816,
        rate(16),
        250,
        (1..=4).filter_map(DriveAddress::new).collect(),
    );
    let mut ring = ring(cfg, standard_drives(4), Vec::new());
    if let Some(node) = ring.drives.get(2) {
        let mut node = node.borrow_mut();
        node.drive_mut()
            .database_mut()
            .set_internal(Idn::from_raw(0x8002), &Value::Unsigned(2))
            .expect("P-0-0002");
    }
    let error = halted_with(&mut ring, 20_000);
    assert_eq!(error.drive, drive(3));
    assert_eq!(error.phase, 2);
    assert_eq!(error.idn, Some(Idn::from_raw(127)));
    // Bits 0, 1 and 3: set, enabled, error (spec-notes, emulated drive).
    assert_eq!(
        error.kind,
        MasterErrorKind::ProcedureFailed { status: 0x000B }
    );
}

/// Runs the capture ring to phase 4, applies `fault` from a moment in phase 4 for `outage`,
/// and returns the errors reported and whether the master came back to phase 4.
fn fault_in_phase_4(fault: impl Fn(Instant, Instant) -> FaultKind) -> (Vec<MasterError>, bool) {
    // The phase-up takes well under 4 s of simulated time at 2 ms (about 900 cycles).
    let before = Instant::ZERO.saturating_add(Duration::from_millis(3990));
    let at = before.saturating_add(Duration::from_millis(10));
    let until = at.saturating_add(Duration::from_millis(100));
    let faults = vec![Fault {
        at,
        kind: fault(at, until),
    }];
    let mut ring = ring(MasterConfig::capture_ring(), standard_drives(4), faults);
    ring.run_until(before);
    assert_eq!(ring.master.borrow().progress(), Progress::Cyclic);
    let errors_before = ring.master.borrow_mut().take_errors();
    assert!(errors_before.is_empty(), "{errors_before:?}");
    ring.run_until(until);
    let errors = ring.master.borrow_mut().take_errors();
    let back = ring.run_to_phase(4, 3000).is_some() && {
        ring.run_cycles(50);
        ring.master.borrow().progress() == Progress::Cyclic
    };
    assert!(ring.master.borrow().status().restarts >= 1);
    (errors, back)
}

// 410B §4.1 2H.13 FIBBR: no edges on the receive line. A broken fibre ends phase 4 with
// "ring broken"; after the repair the master brings the ring up again by itself.
#[test]
fn a_broken_fibre_is_reported_and_the_ring_comes_back() {
    let (errors, back) = fault_in_phase_4(|_, until| FaultKind::FibreBreak {
        segment: 2,
        until: Some(until),
    });
    let first = errors.first().expect("an error");
    assert_eq!(first.kind, MasterErrorKind::RingBroken, "{errors:?}");
    assert_eq!(first.phase, 4);
    assert!(back, "back in phase 4");
}

// A drive powered off stops repeating: the master loses its ATs and the MST (reported as
// ring broken or MST lost), and after power-on (the drive node starts over) it is back in
// phase 4.
#[test]
fn a_drive_powered_off_is_reported_and_the_ring_comes_back() {
    let (errors, back) = fault_in_phase_4(|_, until| FaultKind::PowerOff {
        node: 2,
        until: Some(until),
    });
    let first = errors.first().expect("an error");
    assert!(
        matches!(
            first.kind,
            MasterErrorKind::RingBroken | MasterErrorKind::MstLost
        ),
        "{errors:?}"
    );
    assert_eq!(first.phase, 4);
    assert!(back, "back in phase 4");
}
