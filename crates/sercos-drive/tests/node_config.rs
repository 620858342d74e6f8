//! The drive node (`sercos_drive::node::DriveNode`): made from a TOML IDN file, the bit
//! rate from P-0-0002, and the emulated drive as the slave driver's device (cyclic lengths
//! from S-0-0015, phases refused without the transition checks, status word).

use std::path::Path;

use sercdrv::slave::{CyclicLengths, SlaveConfig, SlaveDevice, SlaveError};
use sercon_regs::Variant;
use sercon_regs::host::{HostProgram, Wake};
use sercon_regs::{Register, SerconBusExt};
use sercos_drive::database::IdnDatabase;
use sercos_drive::drive::EmulatedDrive;
use sercos_drive::node::{DriveNode, NodeError};
use sercos_wire::attribute::Value;
use sercos_wire::idn::Idn;
use sercos_wire::telegram::CommunicationPhase;
use sercos_wire::time::{BitRate, Instant};

const TOML: &str = r#"
[[parameter]]
idn = "P-0-0002"
value = 8

[[parameter]]
idn = "S-0-0015"
value = 2
"#;

// spec-notes "IDN attributes ... emulated drive": P-0-0002 is the drive's bit rate switch;
// the node takes the line rate from it.
#[test]
fn node_from_toml_takes_the_bit_rate_from_p_0_0002() {
    let node =
        DriveNode::from_toml(Variant::Sercon816, 12, TOML, Path::new("drive.toml")).expect("node");
    assert_eq!(node.address(), 12);
    assert_eq!(node.driver().config().bit_rate, BitRate::Mbit8);
    assert_eq!(node.phase(), CommunicationPhase::Phase0);
    assert_eq!(node.drive().database().number(Idn::from_raw(15)), Some(2));
}

// 410B §2 SBAUD: the 410B makes f_SCLK/16 or /32 only (4 or 2 Mbit/s at 64 MHz); 8 Mbit/s
// is refused when the node is made (the RAM layout checks the rate against the variant).
#[test]
fn a_410b_node_refuses_8_mbit() {
    let node = DriveNode::from_toml(Variant::Sercon410b, 12, TOML, Path::new("drive.toml"));
    assert!(
        matches!(node, Err(NodeError::Slave(SlaveError::Layout(_)))),
        "{node:?}"
    );
}

// 816 §2.3.1: the bit rate is SCLK divided by 4, 8, 16 or 32; an SCLK of 50 MHz makes no
// 2 Mbit/s, so the start fails and the driver stays stopped (and sends nothing).
#[test]
fn a_start_the_clocks_cannot_serve_stops_the_driver() {
    let mut config = SlaveConfig::new(Variant::Sercon816, 4);
    config.sclk_hz = 50_000_000;
    let mut node = DriveNode::with_config(config, IdnDatabase::standard()).expect("node");
    let mut chip = sercon_model::Chip::new(sercon_model::ChipConfig::sercon816());
    node.wake(&mut chip, Instant::ZERO, Wake::Start);
    assert!(matches!(
        node.driver().failure(),
        Some(SlaveError::BitRate {
            rate: BitRate::Mbit2,
            ..
        })
    ));
    assert_eq!(chip.read(Register::Ctrl3) & (1 << 8), 0, "ENTMT stays 0");
}

// Errors of the TOML file and of the address reach the caller as `NodeError`.
#[test]
fn bad_files_and_addresses_are_errors() {
    let bad = DriveNode::from_toml(
        Variant::Sercon816,
        1,
        "[[parameter]]\nidn = \"S-0-9999x\"\n",
        Path::new("bad.toml"),
    );
    assert!(matches!(bad, Err(NodeError::Config(_))), "{bad:?}");
    let zero = DriveNode::new(Variant::Sercon816, 0, IdnDatabase::standard());
    assert!(matches!(
        zero,
        Err(NodeError::Slave(SlaveError::InvalidAddress(0)))
    ));
    let missing = DriveNode::from_file(Variant::Sercon816, 1, Path::new("/nonexistent.toml"));
    assert!(matches!(missing, Err(NodeError::Config(_))));
}

// Beckhoff AX2000 IDN 15 table (telegram_layout): type 2 = S-0-0036 in the MDT, S-0-0040 in
// the AT, 4 bytes each; type 0 = none.
#[test]
fn cyclic_lengths_follow_the_telegram_type() {
    let mut db = IdnDatabase::standard();
    let drive = EmulatedDrive::new(db.clone(), Instant::ZERO);
    assert_eq!(drive.cyclic_lengths(), Ok(CyclicLengths::default()));
    db.set_internal(Idn::from_raw(15), &Value::Unsigned(2))
        .expect("S-0-0015");
    let drive = EmulatedDrive::new(db, Instant::ZERO);
    assert_eq!(
        drive.cyclic_lengths(),
        Ok(CyclicLengths {
            mdt_data_bytes: 4,
            at_data_bytes: 4
        })
    );
}

// sercos-facts.md S-0-0127: the device refuses phase 3 without the transition check, and
// phases step up one at a time.
#[test]
fn the_device_refuses_phase_3_without_the_check() {
    let mut drive = EmulatedDrive::new(IdnDatabase::standard(), Instant::ZERO);
    let now = Instant::ZERO;
    for phase in [
        CommunicationPhase::Phase0,
        CommunicationPhase::Phase1,
        CommunicationPhase::Phase2,
    ] {
        SlaveDevice::enter_phase(&mut drive, now, phase).expect("0-2");
    }
    assert!(SlaveDevice::enter_phase(&mut drive, now, CommunicationPhase::Phase3).is_err());
    assert!(SlaveDevice::enter_phase(&mut drive, now, CommunicationPhase::Phase4).is_err());
    // Status word bits 15-14 = 01 below phase 4 (spec-notes, emulated drive).
    assert_eq!(SlaveDevice::status_word(&mut drive, now) >> 14, 0b01);
}
