//! The SERCDRV slave (`sercdrv::slave`, run by `sercos_drive::node::DriveNode`) on a
//! sercon-model chip, answering a hand-driven master chip on the line through the phases:
//! detection in phase 1, the service channel in phase 2, the transition checks, cyclic data
//! in phases 3 and 4, on both controller variants.

mod slave_support;

use sercdrv::service_channel::{CommandStatus, ErrorKind, Request};
use sercdrv::slave::{PhaseRefusal, SlaveDriverEvent};
use sercon_regs::{SerconBus, Variant};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::ServiceError;
use sercos_wire::telegram::CommunicationPhase;
use slave_support::{ADDRESS, Ring, TELEGRAM_TYPE};

const VARIANTS: [Variant; 2] = [Variant::Sercon816, Variant::Sercon410b];

/// S-0-0127 / S-0-0128, phase 3 / 4 transition check (sercos-facts.md).
const PHASE_3_CHECK: Idn = Idn::from_raw(127);
const PHASE_4_CHECK: Idn = Idn::from_raw(128);
/// S-0-0036 velocity command, S-0-0040 velocity feedback (telegram type 2).
const VELOCITY_COMMAND: Idn = Idn::from_raw(36);
const VELOCITY_FEEDBACK: Idn = Idn::from_raw(40);

/// Runs the master through phases 0, 1 and 2 (a few cycles each).
fn up_to_phase_2(ring: &mut Ring) {
    ring.cycles(3);
    ring.master_phase(1);
    ring.cycles(4);
    ring.master_phase(2);
    ring.cycles(4);
    assert_eq!(ring.node.phase(), CommunicationPhase::Phase2);
}

/// Phase 2 as a master does it: telegram type 2, the cycle's parameters (S-0-0001, 2, 6,
/// 89, 8, 7, 9, 10), then S-0-0127 set and polled until executed.
fn configure_and_check(ring: &mut Ring) {
    ring.transact(Request::write_value(TELEGRAM_TYPE, vec![2]))
        .result
        .expect("S-0-0015");
    let writes = ring.timing.parameter_writes(ADDRESS).expect("drive");
    for (idn, value) in writes {
        ring.transact(Request::write_value(idn, vec![value as u16]))
            .result
            .unwrap_or_else(|e| panic!("{idn}: {e}"));
    }
    ring.transact(Request::set_command(PHASE_3_CHECK))
        .result
        .expect("set S-0-0127");
    let status = ring
        .transact(Request::command_status(PHASE_3_CHECK))
        .result
        .expect("poll");
    let status = CommandStatus(status.words[0]);
    assert!(status.is_finished() && !status.is_error(), "{status:?}");
}

// sercos-telegrams.md "Amplifier Telegram": in phases 1-2 the slave sends its AT only when
// it receives an MDT with its address (410B §4.2.1 EN = 3, 25H PHAS12 / FLMDTADR).
#[test]
fn phase_1_detection_answers_once_per_mdt_to_its_address() {
    for variant in VARIANTS {
        let mut ring = Ring::new(variant);
        ring.cycles(3);
        // Phase 0: the master sends only MSTs; the slave sends nothing.
        assert!(
            ring.slave_ats_since(sercos_wire::time::Instant::ZERO)
                .is_empty()
        );
        ring.master_phase(1);
        ring.cycles(2);
        assert_eq!(ring.node.phase(), CommunicationPhase::Phase1, "{variant:?}");
        let from = ring.now;
        ring.cycles(6);
        let mdts = ring.master_mdts_since(from);
        let ats = ring.slave_ats_since(from);
        assert_eq!(mdts.len(), 6, "{variant:?}");
        assert!(mdts.iter().all(|m| m.bytes[0] == ADDRESS));
        // One AT per MDT: each cycle's AT answers the MDT of the previous cycle.
        assert!(
            (5..=6).contains(&ats.len()),
            "{variant:?}: {} ATs",
            ats.len()
        );
        assert!(
            ats.iter()
                .all(|a| a.bytes[0] == ADDRESS && a.bytes.len() == 5)
        );
        // Status word bits 15-14 = 01: ready for power-up below phase 4 (spec-notes).
        let status = u16::from_le_bytes([ats[0].bytes[1], ats[0].bytes[2]]);
        assert_eq!(status >> 14, 0b01, "{status:04X}");

        // An MDT to another address: FLMDTADR = 0 and no AT (410B §4.2.1 EN = 3).
        let mdt_header = ring.layout.map.blocks[0].telegrams[1].header;
        let word0 = ring.master.read_ram(mdt_header);
        ring.master.write_ram(mdt_header, (word0 & 0xFF00) | 9);
        ring.cycles(2);
        let from = ring.now;
        ring.cycles(4);
        assert!(ring.slave_ats_since(from).is_empty(), "{variant:?}");
    }
}

// sercos-facts.md "IDNs" and "Service channel errors"; 410B §4.2.4 slave container served
// from the drive's IDN store: S-0-0017 is the drive's list, a read-only IDN is refused
// with 7004H.
#[test]
fn service_channel_reads_s_0_0017_and_refuses_a_read_only_write() {
    for variant in VARIANTS {
        let mut ring = Ring::new(variant);
        up_to_phase_2(&mut ring);
        let list = ring
            .transact(Request::read_value(Idn::from_raw(17)))
            .result
            .expect("S-0-0017");
        let expected = ring
            .node
            .drive()
            .database()
            .read(Idn::from_raw(17), Element::OperationData)
            .expect("list");
        assert_eq!(list.words, expected, "{variant:?}");
        // Current length in bytes, then the list: S-0-0017 holds every IDN of the drive.
        assert_eq!(
            usize::from(list.words[0]) / 2,
            ring.node.drive().database().len()
        );
        let error = ring
            .transact(Request::write_value(Idn::from_raw(3), vec![10]))
            .result
            .expect_err("S-0-0003 is read only");
        assert_eq!(
            (error.idn, error.element, error.kind),
            (
                Idn::from_raw(3),
                Element::OperationData,
                ErrorKind::Drive(ServiceError::OperationDataReadOnly)
            ),
            "{variant:?}"
        );
        ring.transact(Request::write_value(
            Idn::from_raw(2),
            vec![ring.timing.cycle_time_us as u16],
        ))
        .result
        .expect("S-0-0002");
        let events = ring.node.take_events();
        assert!(events.iter().any(|e| matches!(
            e,
            SlaveDriverEvent::Service(sercdrv::service_channel::SlaveEvent::Refused { .. })
        )));
    }
}

// sercos-facts.md S-0-0127: phase 3 only after the transition check; the slave leaves PHAS1
// at 0 so the chip reports INT_PHASERR and processes no block (410B §4.1 0AH, 4H.6).
#[test]
fn phase_3_is_refused_without_s_0_0127() {
    for variant in VARIANTS {
        let mut ring = Ring::new(variant);
        up_to_phase_2(&mut ring);
        ring.node.take_events();
        ring.master_phase(3);
        ring.cycles(1);
        let from = ring.now;
        ring.cycles(4);
        assert_eq!(ring.node.phase(), CommunicationPhase::Phase2, "{variant:?}");
        assert!(ring.slave_ats_since(from).is_empty(), "{variant:?}");
        let refusals: Vec<_> = ring
            .node
            .take_events()
            .into_iter()
            .filter(|e| matches!(e, SlaveDriverEvent::PhaseRefused { .. }))
            .collect();
        assert_eq!(
            refusals,
            vec![SlaveDriverEvent::PhaseRefused {
                from: CommunicationPhase::Phase2,
                requested: 3,
                reason: PhaseRefusal::TransitionCheckNotExecuted(PHASE_3_CHECK),
            }],
            "{variant:?}"
        );
        // Back in phase 2 the slave answers again.
        ring.master_phase(2);
        ring.cycles(2);
        let from = ring.now;
        ring.cycles(3);
        assert!(!ring.slave_ats_since(from).is_empty(), "{variant:?}");
    }
}

// sercos-telegrams.md "Data Record": in phases 3-4 the command value in the drive's MDT
// record reaches the drive (S-0-0036 into the velocity loop) and the feedback (S-0-0040)
// comes back in its AT at t1 (S-0-0006), status word bits 15-14 = 11 when on and enabled.
#[test]
fn phase_4_command_value_reaches_the_motion_model_and_feedback_returns() {
    for variant in VARIANTS {
        let mut ring = Ring::new(variant);
        up_to_phase_2(&mut ring);
        configure_and_check(&mut ring);
        ring.master_phase(3);
        ring.cycles(3);
        assert_eq!(ring.node.phase(), CommunicationPhase::Phase3, "{variant:?}");
        let from = ring.now;
        ring.cycles(3);
        let ats = ring.slave_ats_since(from);
        assert_eq!(ats.len(), 3, "{variant:?}: one AT per cycle in phase 3");
        // ADR + status + service + 4 bytes of S-0-0040.
        assert!(ats.iter().all(|a| a.bytes.len() == 9));
        ring.transact(Request::set_command(PHASE_4_CHECK))
            .result
            .expect("S-0-0128");
        ring.cycles(2);
        ring.master_phase(4);
        ring.cycles(2);
        assert_eq!(ring.node.phase(), CommunicationPhase::Phase4, "{variant:?}");

        // Control word 111 (drive on, enable, restart), velocity command 100 rpm
        // (4 decimal places, catalogue).
        let drive = ring.master_drive_ram();
        let command = drive.command.data;
        ring.master.write_ram(command, 0xE000);
        let rpm = 1_000_000i32;
        ring.master.write_ram(command + 2, rpm as u16);
        ring.master.write_ram(command + 3, (rpm >> 16) as u16);
        ring.cycles(200);
        let axis = ring.node.drive().axis().velocity_rpm();
        assert!(axis > 50.0 && axis <= 100.0, "{variant:?}: {axis} rpm");
        let feedback = drive.feedback.data;
        let status = ring.master.read_ram(feedback);
        assert_eq!(status >> 14, 0b11, "{variant:?}: {status:04X}");
        let low = ring.master.read_ram(feedback + 2);
        let high = ring.master.read_ram(feedback + 3);
        let fed_back = i64::from(i32::from(low as i16) & 0xFFFF | (i32::from(high as i16) << 16));
        let in_drive = ring
            .node
            .drive()
            .database()
            .number(VELOCITY_FEEDBACK)
            .expect("S-0-0040") as i64;
        assert!(fed_back > 500_000, "{variant:?}: {fed_back}");
        // The AT carries the value of the previous cycle's end: within one cycle's change.
        assert!(
            (fed_back - in_drive).abs() < 100_000,
            "{fed_back} vs {in_drive}"
        );
        assert_eq!(
            ring.node.drive().database().number(VELOCITY_COMMAND),
            Some(i128::from(rpm))
        );
    }
}
