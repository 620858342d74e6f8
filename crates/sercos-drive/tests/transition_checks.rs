//! The transition checks S-0-0127 / S-0-0128 as the captures' master uses them: set, poll
//! and acknowledge (cancel, write 0) *before* it switches the phase. The drive remembers that
//! a check passed until a parameter the check read is written or the phase drops
//! (docs/spec-notes.md, "Driver slave and drive node").

mod support;

use sercos_drive::drive::EmulatedDrive;
use sercos_drive::procedure::CommandStatus;
use sercos_wire::telegram::CommunicationPhase;
use support::{idn, write};

/// A drive in phase 2 with the captures' timing and telegram configuration for drive 1.
fn configured() -> EmulatedDrive {
    support::in_phase_2_with(&support::CAPTURE_TELEGRAM)
}

// captures (`sercon capture transcript`): S-0-0127 = 3, poll, = 0 in phase 2, then phase 3;
// S-0-0128 = 3, poll, = 0 in phase 3, then phase 4. sercos-facts.md S-0-0127/S-0-0128.
#[test]
fn an_acknowledged_check_still_allows_the_step() {
    let mut drive = configured();
    write(&mut drive, "S-0-0127", &[3]);
    assert_eq!(
        drive.database().command_status(idn("S-0-0127")),
        CommandStatus::Executed
    );
    write(&mut drive, "S-0-0127", &[0]);
    assert_eq!(
        drive.database().command_status(idn("S-0-0127")),
        CommandStatus::NotSet
    );
    assert!(drive.database().transition_check_passed(idn("S-0-0127")));
    assert_eq!(drive.set_phase(CommunicationPhase::Phase3), Ok(()));
    write(&mut drive, "S-0-0128", &[3]);
    write(&mut drive, "S-0-0128", &[0]);
    assert_eq!(drive.set_phase(CommunicationPhase::Phase4), Ok(()));
}

// spec-notes: a write of a parameter the check read (here S-0-0002) makes the pass void.
#[test]
fn a_checked_parameter_written_after_the_check_voids_it() {
    let mut drive = configured();
    write(&mut drive, "S-0-0127", &[3]);
    write(&mut drive, "S-0-0127", &[0]);
    write(&mut drive, "S-0-0002", &[1000]);
    assert!(!drive.database().transition_check_passed(idn("S-0-0127")));
    assert!(drive.set_phase(CommunicationPhase::Phase3).is_err());
    // A parameter the check does not read (S-0-0032) keeps it.
    write(&mut drive, "S-0-0002", &[2000]);
    write(&mut drive, "S-0-0127", &[3]);
    write(&mut drive, "S-0-0127", &[0]);
    write(&mut drive, "S-0-0032", &[2]);
    assert!(drive.database().transition_check_passed(idn("S-0-0127")));
}

// spec-notes: a drop of the phase forgets every check.
#[test]
fn a_drop_to_phase_0_forgets_the_checks() {
    let mut drive = configured();
    write(&mut drive, "S-0-0127", &[3]);
    assert_eq!(drive.set_phase(CommunicationPhase::Phase0), Ok(()));
    assert!(!drive.database().transition_check_passed(idn("S-0-0127")));
    for phase in [CommunicationPhase::Phase1, CommunicationPhase::Phase2] {
        assert_eq!(drive.set_phase(phase), Ok(()));
    }
    assert!(drive.set_phase(CommunicationPhase::Phase3).is_err());
}

// sercos-facts.md "Procedure commands": a failing run (error bit) removes an earlier pass.
#[test]
fn a_failing_rerun_voids_an_earlier_pass() {
    let mut drive = configured();
    write(&mut drive, "S-0-0127", &[3]);
    write(&mut drive, "S-0-0127", &[0]);
    // t1 beyond t2 - tATMT: the check fails. Writing S-0-0006 voids the pass already; run
    // the check again and see the error kept.
    write(&mut drive, "S-0-0006", &[1900]);
    write(&mut drive, "S-0-0127", &[3]);
    assert_eq!(
        drive.database().command_status(idn("S-0-0127")),
        CommandStatus::Error
    );
    assert!(!drive.database().transition_check_passed(idn("S-0-0127")));
    assert!(drive.set_phase(CommunicationPhase::Phase3).is_err());
}
