//! The emulated drive from phase 2 to phase 4 with the captures' configuration, then
//! following velocity commands by the control word (sercos-telegrams.md, MDT control word
//! bits 15–13; AT status word bits 15–13, 5).

mod support;

use sercos_drive::drive::EmulatedDrive;
use sercos_wire::idn::Element;
use sercos_wire::telegram::{CommunicationPhase, ReadyToOperate};
use sercos_wire::time::{Duration, Instant};
use support::{idn, write};

fn phased_up() -> EmulatedDrive {
    let mut drive = support::in_phase_2_with(&support::CAPTURE_TELEGRAM);
    // sercos-facts.md: phase 3 only after S-0-0127 executed.
    assert!(drive.set_phase(CommunicationPhase::Phase4).is_err());
    assert!(drive.set_phase(CommunicationPhase::Phase3).is_err());
    write(&mut drive, "S-0-0127", &[3]);
    assert!(drive.status_word().command_change());
    assert!(drive.set_phase(CommunicationPhase::Phase3).is_ok());
    write(&mut drive, "S-0-0127", &[0]);
    write(&mut drive, "S-0-0128", &[3]);
    assert!(drive.set_phase(CommunicationPhase::Phase4).is_ok());
    write(&mut drive, "S-0-0128", &[0]);
    drive
}

#[test]
fn follows_velocity_with_lag_when_on_enabled_restart() {
    let mut drive = phased_up();
    assert_eq!(
        drive.status_word().ready_to_operate(),
        ReadyToOperate::PowerReady
    );
    let cycle = Duration::from_micros(2000);
    let mut now = Instant::ZERO;
    // Control word 111 in bits 15–13: follow the command (1000 rpm, 4 decimal places).
    for _ in 0..5 {
        now += cycle;
        assert!(
            drive
                .receive_mdt_record(now, &support::velocity_record(0xE000, 10_000_000))
                .is_ok()
        );
    }
    assert_eq!(
        drive.status_word().ready_to_operate(),
        ReadyToOperate::ReadyToOperate
    );
    now += cycle;
    drive.advance_to(now);
    // P-0-0001 = 5.0 ms: after 10 ms (two time constants) 1 − e^−2 ≈ 86.5 %.
    let velocity = drive.axis().velocity_rpm();
    assert!((velocity - 864.7).abs() < 1.0, "{velocity}");
    // The AT carries S-0-0011, S-0-0051, P-0-0019 (12-byte record, 8 bytes of data).
    let at = drive.at_cyclic_data();
    assert_eq!(at.len(), 8);
    let position = i32::from_le_bytes([at[2], at[3], at[4], at[5]]);
    assert!(position > 0);

    // Drive halt (bit 13 = 0): decelerates to standstill.
    for _ in 0..100 {
        now += cycle;
        assert!(
            drive
                .receive_mdt_record(now, &support::velocity_record(0xC000, 10_000_000))
                .is_ok()
        );
    }
    assert!(drive.axis().velocity_rpm().abs() < 0.01);
    let message = drive
        .database()
        .get(idn("S-0-0095"))
        .map(|p| p.words().to_vec());
    assert!(message.is_some_and(|w| w.len() > 2));
}

#[test]
fn simulated_fault_is_a_class_1_error_until_reset() {
    let mut drive = phased_up();
    let mut now = Instant::ZERO + Duration::from_millis(2);
    assert!(
        drive
            .receive_mdt_record(now, &support::velocity_record(0xE000, 10_000_000))
            .is_ok()
    );
    write(&mut drive, "P-0-0003", &[1]);
    now += Duration::from_millis(2);
    assert!(
        drive
            .receive_mdt_record(now, &support::velocity_record(0xE000, 10_000_000))
            .is_ok()
    );
    // AT status word bit 13 and ready-to-operate 00 on a class 1 error.
    let status = drive.status_word();
    assert!(status.shutdown_error());
    assert_eq!(
        status.ready_to_operate(),
        ReadyToOperate::NotReadyForPowerUp
    );
    // S-0-0099 fails while the fault is present, succeeds after it is gone.
    write(&mut drive, "S-0-0099", &[3]);
    assert_eq!(
        drive
            .database()
            .read(idn("S-0-0099"), Element::OperationData),
        Ok(vec![0x000B])
    );
    write(&mut drive, "S-0-0099", &[0]);
    write(&mut drive, "P-0-0003", &[0]);
    write(&mut drive, "S-0-0099", &[3]);
    assert_eq!(
        drive
            .database()
            .read(idn("S-0-0011"), Element::OperationData),
        Ok(vec![0])
    );
    now += Duration::from_millis(2);
    drive.advance_to(now);
    assert!(!drive.status_word().shutdown_error());
}
