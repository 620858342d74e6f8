//! Shared set-up of the emulated-drive tests: a drive brought to phase 2 with the captures'
//! timing (S-0-0006/0089/0008/0007/0010 as the TC2000R captures' master wrote them to drive 1).

#![allow(dead_code)] // each test file uses its part

use sercos_drive::database::IdnDatabase;
use sercos_drive::drive::EmulatedDrive;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::telegram::CommunicationPhase;
use sercos_wire::time::Instant;

/// The IDN of `text` (`S-0-0001`); an impossible one for bad text, so a test fails loudly.
pub fn idn(text: &str) -> Idn {
    text.parse().unwrap_or(Idn::from_raw(0xFFFF))
}

/// Writes operation data, asserting that the drive takes it.
pub fn write(drive: &mut EmulatedDrive, name: &str, words: &[u16]) {
    let result = drive
        .database_mut()
        .write(idn(name), Element::OperationData, words);
    assert_eq!(result, Ok(()), "{name}");
}

/// The captures' phase-2 timing writes to drive 1 (`sercon capture transcript`).
pub const CAPTURE_TIMING: [(&str, &[u16]); 5] = [
    ("S-0-0006", &[92]),
    ("S-0-0089", &[1782]),
    ("S-0-0008", &[1965]),
    ("S-0-0007", &[1698]),
    ("S-0-0010", &[32]),
];

/// The captures' telegram configuration: type 7, AT [S-0-0011, S-0-0051, P-0-0019], MDT
/// [S-0-0036] (variable-length lists: current and maximum length in bytes, then the IDNs).
pub const CAPTURE_TELEGRAM: [(&str, &[u16]); 3] = [
    ("S-0-0015", &[7]),
    ("S-0-0016", &[6, 6, 0x000B, 0x0033, 0x8013]),
    ("S-0-0024", &[2, 2, 0x0024]),
];

/// A standard drive in phase 2 with `writes` applied after the captures' timing.
pub fn in_phase_2_with(writes: &[(&str, &[u16])]) -> EmulatedDrive {
    let mut drive = EmulatedDrive::new(IdnDatabase::standard(), Instant::ZERO);
    for phase in [CommunicationPhase::Phase1, CommunicationPhase::Phase2] {
        assert!(drive.set_phase(phase).is_ok());
    }
    for (name, words) in CAPTURE_TIMING.iter().chain(writes) {
        write(&mut drive, name, words);
    }
    drive
}

/// Steps a drive in phase 2 to phase 4, each step after its transition check (S-0-0127 for
/// phase 3, S-0-0128 for phase 4, set and then cancelled; sercos-facts.md).
pub fn step_to_phase_4(drive: &mut EmulatedDrive) {
    write(drive, "S-0-0127", &[3]);
    assert!(drive.set_phase(CommunicationPhase::Phase3).is_ok());
    write(drive, "S-0-0127", &[0]);
    write(drive, "S-0-0128", &[3]);
    assert!(drive.set_phase(CommunicationPhase::Phase4).is_ok());
    write(drive, "S-0-0128", &[0]);
}

/// An MDT record of telegram type 2: control word, two bytes of service info (0), then the
/// velocity command S-0-0036 (little endian, as on the line).
pub fn velocity_record(control: u16, velocity: i32) -> Vec<u8> {
    let mut bytes = control.to_le_bytes().to_vec();
    bytes.extend([0, 0]);
    bytes.extend(velocity.to_le_bytes());
    bytes
}
