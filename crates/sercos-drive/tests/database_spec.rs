//! The IDN database against sercos-facts.md ("IDNs", "Attribute", "Procedure commands",
//! "Timing parameters", "Service channel errors") and the phase-2 writes of the TC2000R
//! captures (captures/README.md).

use sercos_drive::database::IdnDatabase;
use sercos_drive::procedure::CommandStatus;
use sercos_drive::telegram_layout::{self, CyclicField};
use sercos_wire::attribute::Value;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::{DescriptiveElement, ElementFault, ServiceError};
use sercos_wire::telegram::CommunicationPhase;

fn idn(text: &str) -> Idn {
    text.parse().unwrap_or(Idn::from_raw(0xFFFF))
}

fn phase2() -> IdnDatabase {
    let mut db = IdnDatabase::standard();
    db.set_phase(CommunicationPhase::Phase2);
    db
}

/// The master's phase-2 writes to drive 1 in tc2000r-phaseup.nrzi (decoded service channel).
fn capture_writes(db: &mut IdnDatabase) -> Result<(), ServiceError> {
    let op = Element::OperationData;
    db.write(idn("S-0-0001"), op, &[2000])?;
    db.write(idn("S-0-0002"), op, &[2000])?;
    db.write(idn("S-0-0006"), op, &[92])?;
    db.write(idn("S-0-0089"), op, &[1782])?;
    db.write(idn("S-0-0008"), op, &[1965])?;
    db.write(idn("S-0-0007"), op, &[1698])?;
    db.write(idn("S-0-0009"), op, &[1])?;
    db.write(idn("S-0-0010"), op, &[32])?;
    db.write(idn("S-0-0015"), op, &[7])?;
    db.write(idn("S-0-0016"), op, &[6, 6, 0x000B, 0x0033, 0x8013])?;
    db.write(idn("S-0-0024"), op, &[2, 2, 0x0024])
}

#[test]
fn elements_1_to_7_readable() {
    // sercos-facts.md, IDNs: elements 1 IDN, 2 name, 3 attribute, 4 unit, 5 min, 6 max, 7 data.
    let db = IdnDatabase::standard();
    let cycle = idn("S-0-0002");
    assert_eq!(db.read(cycle, Element::Idn), Ok(vec![2]));
    let name = db.read(cycle, Element::Name).unwrap_or_default();
    let text = "communication cycle time tScyc";
    assert_eq!(name.first().copied(), Some(text.len() as u16));
    assert_eq!(db.read(cycle, Element::Attribute).map(|w| w.len()), Ok(2));
    assert_eq!(
        db.read(cycle, Element::Unit),
        Ok(vec![3, 3, 0xB5C2, u16::from(b's')])
    );
    assert_eq!(db.read(cycle, Element::Maximum), Ok(vec![65_000]));
    assert_eq!(db.read(cycle, Element::OperationData), Ok(vec![2000]));
    assert_eq!(
        db.read(idn("S-0-0016"), Element::Minimum),
        Err(ServiceError::Element(
            DescriptiveElement::Minimum,
            ElementFault::NotPresent
        ))
    );
}

#[test]
fn service_errors() {
    // sercos-facts.md, service channel errors.
    let mut db = phase2();
    let op = Element::OperationData;
    assert_eq!(
        db.write(idn("S-0-4000"), op, &[1]),
        Err(ServiceError::IdnNotPresent)
    );
    assert_eq!(
        db.read(idn("S-0-4000"), op),
        Err(ServiceError::IdnNotPresent)
    );
    assert_eq!(
        db.write(idn("S-0-0002"), Element::Idn, &[2]),
        Err(ServiceError::InvalidAccessToElement1)
    );
    assert_eq!(
        db.write(idn("S-0-0002"), Element::Name, &[0, 0]),
        Err(ServiceError::Element(
            DescriptiveElement::Name,
            ElementFault::CannotBeChanged
        ))
    );
    assert_eq!(
        db.write(idn("S-0-0003"), op, &[10]),
        Err(ServiceError::OperationDataReadOnly)
    );
    assert_eq!(
        db.write(idn("S-0-0002"), op, &[]),
        Err(ServiceError::OperationDataTooShort)
    );
    assert_eq!(
        db.write(idn("S-0-0002"), op, &[1, 2]),
        Err(ServiceError::OperationDataTooLong)
    );
    assert_eq!(
        db.write(idn("S-0-0002"), op, &[65_001]),
        Err(ServiceError::OperationDataAboveMaximum)
    );
    assert_eq!(
        db.write(idn("S-0-0009"), op, &[0]),
        Err(ServiceError::OperationDataBelowMinimum)
    );
    // S-0-0016 holds at most 32 bytes.
    let long: Vec<u16> = [34, 34].into_iter().chain([11; 17]).collect();
    assert_eq!(
        db.write(idn("S-0-0016"), op, &long),
        Err(ServiceError::OperationDataTooLong)
    );
    // A procedure command takes only 3 and 0.
    assert_eq!(
        db.write(idn("S-0-0099"), op, &[1]),
        Err(ServiceError::OperationDataInvalid)
    );
}

#[test]
fn write_protection_follows_the_phase() {
    // sercos-facts.md, attribute bits 30–28: S-0-0002 is configured in phase 2 only.
    let mut db = phase2();
    assert_eq!(
        db.write(idn("S-0-0002"), Element::OperationData, &[1000]),
        Ok(())
    );
    db.set_phase(CommunicationPhase::Phase3);
    assert_eq!(
        db.write(idn("S-0-0002"), Element::OperationData, &[2000]),
        Err(ServiceError::OperationDataWriteProtectedNow)
    );
    assert_eq!(
        db.read(idn("S-0-0002"), Element::OperationData),
        Ok(vec![1000])
    );
}

#[test]
fn capture_configuration_passes_the_phase_3_check() {
    // captures: the master writes the timing and telegram configuration, then S-0-0127 = 3.
    let mut db = phase2();
    assert_eq!(capture_writes(&mut db), Ok(()));
    assert_eq!(
        db.write(idn("S-0-0127"), Element::OperationData, &[3]),
        Ok(())
    );
    assert_eq!(db.command_status(idn("S-0-0127")), CommandStatus::Executed);
    assert_eq!(
        db.read(idn("S-0-0127"), Element::OperationData),
        Ok(vec![0x0007])
    );
    assert!(db.command_change());
    // 0 cancels / acknowledges.
    assert_eq!(
        db.write(idn("S-0-0127"), Element::OperationData, &[0]),
        Ok(())
    );
    assert_eq!(db.command_status(idn("S-0-0127")), CommandStatus::NotSet);
    assert!(!db.command_change());

    let layout = telegram_layout::layout(&db);
    let layout = layout.unwrap_or_default();
    assert_eq!(
        layout.mdt,
        vec![CyclicField {
            idn: idn("S-0-0036"),
            offset: 4,
            len: 4
        }]
    );
    assert_eq!(
        layout.mdt_record_len(),
        8,
        "captures: 8-byte records in phases 3-4"
    );
    assert_eq!(layout.at_record_len(), 4 + 2 + 4 + 2);
}

#[test]
fn phase_3_check_rejects_bad_timing() {
    // sercos-facts.md: t1min ≤ t1 < t2 − tATMT.
    let mut db = phase2();
    assert_eq!(capture_writes(&mut db), Ok(()));
    assert_eq!(
        db.write(idn("S-0-0006"), Element::OperationData, &[10]),
        Ok(())
    );
    assert_eq!(
        db.write(idn("S-0-0127"), Element::OperationData, &[3]),
        Ok(())
    );
    assert_eq!(db.command_status(idn("S-0-0127")), CommandStatus::Error);
    let message = match db.get(idn("S-0-0095")).and_then(|p| p.value().ok()) {
        Some(Value::Text(bytes)) => String::from_utf8_lossy(&bytes).into_owned(),
        _ => String::new(),
    };
    assert!(message.contains("t1 = 10"), "{message}");

    // t2 + MDT duration + S-0-0090 < t3: t3 = t2 + 1 is too early.
    let mut db = phase2();
    assert_eq!(capture_writes(&mut db), Ok(()));
    assert_eq!(
        db.write(idn("S-0-0008"), Element::OperationData, &[1783]),
        Ok(())
    );
    assert_eq!(
        db.write(idn("S-0-0127"), Element::OperationData, &[3]),
        Ok(())
    );
    assert_eq!(db.command_status(idn("S-0-0127")), CommandStatus::Error);

    // An AT list entry outside S-0-0187.
    let mut db = phase2();
    assert_eq!(capture_writes(&mut db), Ok(()));
    assert_eq!(
        db.write(idn("S-0-0016"), Element::OperationData, &[2, 2, 0x0024]),
        Ok(())
    );
    assert_eq!(
        db.write(idn("S-0-0127"), Element::OperationData, &[3]),
        Ok(())
    );
    assert_eq!(db.command_status(idn("S-0-0127")), CommandStatus::Error);
}

#[test]
fn standard_telegram_types() {
    // Telegram types 0–6 (Beckhoff AX2000 IDN 15 table).
    let mut db = phase2();
    let cases: [(u16, &[&str], &[&str]); 4] = [
        (0, &[], &[]),
        (2, &["S-0-0036"], &["S-0-0040"]),
        (5, &["S-0-0047", "S-0-0036"], &["S-0-0051", "S-0-0040"]),
        (6, &["S-0-0036"], &[]),
    ];
    for (kind, mdt, at) in cases {
        assert_eq!(
            db.write(idn("S-0-0015"), Element::OperationData, &[kind]),
            Ok(())
        );
        let layout = telegram_layout::layout(&db).unwrap_or_default();
        let names =
            |fields: &[CyclicField]| fields.iter().map(|f| f.idn.to_string()).collect::<Vec<_>>();
        assert_eq!(names(&layout.mdt), mdt.to_vec(), "type {kind}");
        assert_eq!(names(&layout.at), at.to_vec(), "type {kind}");
    }
    assert_eq!(
        db.write(idn("S-0-0015"), Element::OperationData, &[8]),
        Err(ServiceError::OperationDataAboveMaximum)
    );
}

#[test]
fn s_0_0017_lists_every_idn() {
    let db = IdnDatabase::standard();
    let words = db
        .read(idn("S-0-0017"), Element::OperationData)
        .unwrap_or_default();
    assert_eq!(words.first().copied(), Some((db.len() * 2) as u16));
}
