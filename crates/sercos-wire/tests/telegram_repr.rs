//! Telegram views and representations: concrete bytes, parse(emit(repr)) = repr, and arbitrary
//! bytes never panic (sercos-telegrams.md; ERRATA.md, Telegrams).

use proptest::prelude::*;
use sercos_wire::address::{Address, DriveAddress};
use sercos_wire::idn::Element;
use sercos_wire::telegram::{
    AtPacket, AtRecordRepr, AtRepr, CommunicationPhase, ControlWord, DataRecord, DataRecordRepr,
    MdtPacket, MdtRecordRepr, MdtRepr, MstPacket, MstRepr, Origin, StatusWord, Telegram,
    TelegramError, TelegramKind, TelegramRepr, classify,
};

#[test]
fn mst_phase_2_is_ff_02() {
    // sercos-telegrams.md, MST: ADR 255, one byte, bits 2–0 = phase.
    let repr = TelegramRepr::Mst(MstRepr::new(CommunicationPhase::Phase2));
    assert_eq!(repr.to_vec(), [0xFF, 0x02]);
    let parsed = TelegramRepr::parse_bytes(&[0xFF, 0x02], Origin::Master).expect("an MST");
    assert_eq!(parsed, repr);
    let TelegramRepr::Mst(mst) = parsed else {
        panic!("classified as {:?}", parsed.kind())
    };
    assert_eq!(mst.phase(), Ok(CommunicationPhase::Phase2));
}

#[test]
fn mst_keeps_bits_7_to_3_and_reports_unused_phases() {
    // sercos-telegrams.md, MST: only bits 2–0 are the phase; the rest is kept raw
    // (410B register 0AH PHAS0 is 8 bits and resets to 0FFH).
    let packet = MstPacket::new_checked(&[0xFF, 0xFF][..]).expect("2 bytes");
    assert_eq!(packet.phase_bits(), 7);
    assert_eq!(packet.phase(), Err(TelegramError::UnknownPhase(7)));
    let repr = MstRepr::parse(&packet).expect("unknown phases still parse");
    assert_eq!(repr.other_bits(), 0xF8);
    assert_eq!(repr.phase_byte(), 0xFF);
    assert_eq!(TelegramRepr::Mst(repr).to_vec(), [0xFF, 0xFF]);
    assert_eq!(
        MstRepr::new(CommunicationPhase::Phase4)
            .with_other_bits(0x80)
            .to_string(),
        "MST phase 4 (byte 84H)"
    );
}

#[test]
fn mst_must_be_two_bytes_to_255() {
    assert_eq!(
        MstPacket::new_checked(&[0xFF][..]),
        Err(TelegramError::Truncated {
            what: "MST",
            needed: 2,
            got: 1
        })
    );
    assert_eq!(
        MstPacket::new_checked(&[0xFF, 0, 0][..]),
        Err(TelegramError::MstTooLong { got: 3 })
    );
    let packet = MstPacket::new_checked(&[0x01, 0x02][..]).expect("2 bytes");
    assert_eq!(
        MstRepr::parse(&packet),
        Err(TelegramError::BadAddress {
            kind: TelegramKind::Mst,
            address: Address::from(1)
        })
    );
}

#[test]
fn phase_1_mdt_bytes() {
    // The captures (../shared/captures/README.md): phase 1 MDTs are
    // `ADR ctrl_lo ctrl_hi svc_lo svc_hi`; words low byte first (ERRATA.md, Telegrams).
    let bytes = [0x03, 0x08, 0x00, 0x34, 0x12];
    assert_eq!(classify(&bytes, Origin::Master), Ok(TelegramKind::Mdt));
    let repr = TelegramRepr::parse_bytes(&bytes, Origin::Master).expect("an MDT");
    let TelegramRepr::Mdt(MdtRepr::Single { address, record }) = repr else {
        panic!("not a single-drive MDT: {repr:?}")
    };
    assert_eq!(address.get(), 3);
    assert_eq!(record.word.raw(), 0x0008);
    assert_eq!(record.word.data_block_element(), Element::Idn);
    assert_eq!(record.service_info, 0x1234);
    assert!(record.data_block.is_empty());
    assert_eq!(repr.to_vec(), bytes);
}

#[test]
fn broadcast_mdt_records_by_offset() {
    // sercos-telegrams.md, MDT phases 3–4: ADR 255, one record per drive at a byte offset.
    // Offsets count from the first byte after ADR.
    let mut bytes = [0u8; 1 + 4 * 8];
    bytes[0] = 0xFF;
    let mut packet = MdtPacket::new_checked(&mut bytes[..]).expect("long enough");
    for drive in 0..4u8 {
        let value = [drive, drive, drive, drive];
        let record = MdtRecordRepr {
            word: ControlWord::new()
                .with_drive_on(true)
                .with_drive_enable(true)
                .with_drive_restart(true),
            service_info: u16::from(drive) << 8,
            data_block: &value,
        };
        packet
            .set_record_at(usize::from(drive) * 8, &record)
            .expect("fits");
    }
    assert_eq!(bytes[1..9], [0x00, 0xE0, 0x00, 0x00, 0, 0, 0, 0]);
    assert_eq!(bytes[25..33], [0x00, 0xE0, 0x00, 0x03, 3, 3, 3, 3]);

    let packet = MdtPacket::new_checked(&bytes[..]).expect("long enough");
    let third = packet.record_at(16, 4).expect("in bounds");
    assert_eq!(third.service_info(), 0x0200);
    assert_eq!(third.data_block(), &[2, 2, 2, 2]);
    assert_eq!(
        packet.record_at(28, 4).map(|r| r.len()),
        Err(TelegramError::RecordOutOfBounds {
            offset: 28,
            len: 8,
            available: 32
        })
    );
    let repr = MdtRepr::parse(&packet).expect("valid");
    assert_eq!(repr.address(), Address::Broadcast);
    assert_eq!(
        repr.record_at(24, 4).map(|r| r.data_block),
        Ok(&[3u8, 3, 3, 3][..])
    );
}

#[test]
fn mdt_to_no_station_is_rejected_and_short_ones_too() {
    // sercos-telegrams.md, ADR table: MDT addresses are 1–254 or 255.
    let packet = MdtPacket::new_checked(&[0x00, 0, 0, 0, 0][..]).expect("5 bytes");
    assert_eq!(
        MdtRepr::parse(&packet),
        Err(TelegramError::BadAddress {
            kind: TelegramKind::Mdt,
            address: Address::NoStation
        })
    );
    assert_eq!(
        Telegram::new_checked(&[0x01, 0, 0, 0][..], Origin::Master),
        Err(TelegramError::Truncated {
            what: "MDT",
            needed: 5,
            got: 4
        })
    );
}

#[test]
fn at_bytes_and_sender_address() {
    // sercos-telegrams.md, AT: ADR = sending drive, status word, service info, operation data.
    let bytes = [0x02, 0x06, 0xC0, 0x01, 0x70, 0xAA, 0xBB];
    let packet = AtPacket::new_checked(&bytes[..]).expect("7 bytes");
    assert_eq!(packet.status_word().raw(), 0xC006);
    assert!(packet.status_word().busy());
    assert_eq!(packet.service_info(), 0x7001);
    assert_eq!(packet.data_block(), &[0xAA, 0xBB]);
    let repr = TelegramRepr::parse_bytes(&bytes, Origin::Slave).expect("an AT");
    assert_eq!(repr.address(), Address::from(2));
    assert_eq!(repr.to_vec(), bytes);
    for bad in [0x00, 0xFF] {
        let bytes = [bad, 0, 0, 0, 0];
        assert_eq!(
            TelegramRepr::parse_bytes(&bytes, Origin::Slave),
            Err(TelegramError::BadAddress {
                kind: TelegramKind::At,
                address: Address::from(bad)
            })
        );
    }
}

#[test]
fn classification_by_origin() {
    // sercos-telegrams.md: master + ADR 255 + one data byte = MST; master otherwise = MDT;
    // slave = AT.
    assert_eq!(
        classify(&[0xFF, 0x04], Origin::Master),
        Ok(TelegramKind::Mst)
    );
    assert_eq!(
        classify(&[0xFF, 0, 0, 0, 0], Origin::Master),
        Ok(TelegramKind::Mdt)
    );
    assert_eq!(
        classify(&[0x05, 0x04], Origin::Master),
        Ok(TelegramKind::Mdt)
    );
    assert_eq!(classify(&[0xFF, 0x04], Origin::Slave), Ok(TelegramKind::At));
    assert!(classify(&[], Origin::Master).is_err());
    assert_eq!(TelegramKind::At.origin(), Origin::Slave);
}

#[test]
fn emit_checks_the_buffer_length() {
    let repr = AtRepr {
        address: DriveAddress::MIN,
        record: AtRecordRepr {
            word: StatusWord::new(),
            service_info: 0,
            data_block: &[1, 2],
        },
    };
    let mut short = [0u8; 6];
    assert_eq!(
        repr.emit(&mut AtPacket::new_unchecked(&mut short[..])),
        Err(TelegramError::BufferLength {
            what: "AT",
            needed: 7,
            got: 6
        })
    );
    assert_eq!(short, [0; 6], "nothing written on error");
    let mut record = [0u8; 3];
    assert!(
        DataRecordRepr::<u16> {
            word: 1,
            service_info: 2,
            data_block: &[]
        }
        .emit(&mut DataRecord::new_unchecked(&mut record[..]))
        .is_err()
    );
}

#[test]
fn unchecked_views_of_short_buffers_do_not_panic() {
    let mut empty: [u8; 0] = [];
    let mdt = MdtPacket::new_unchecked(&empty[..]);
    assert_eq!(mdt.address(), Address::NoStation);
    assert!(mdt.message_field().is_empty());
    assert!(mdt.record().is_err());
    let at = AtPacket::new_unchecked(&empty[..]);
    assert_eq!(at.status_word().raw(), 0);
    assert!(at.data_block().is_empty());
    let mut at = AtPacket::new_unchecked(&mut empty[..]);
    at.set_status_word(StatusWord::from_raw(0xFFFF));
    at.set_address(Address::Broadcast);
    let mut one = [0u8; 1];
    let mut record = DataRecord::new_unchecked(&mut one[..]);
    record.set_service_info(0xFFFF);
    assert!(record.data_block_mut().is_empty());
    assert_eq!(one, [0]);
}

// ---- property tests ----

fn drive_address() -> impl Strategy<Value = DriveAddress> {
    (1u8..=254).prop_map(|a| DriveAddress::new(a).expect("1-254"))
}

proptest! {
    #[test]
    fn mst_round_trips(byte in any::<u8>()) {
        let repr = TelegramRepr::Mst(MstRepr::from_phase_byte(byte));
        let bytes = repr.to_vec();
        prop_assert_eq!(&bytes, &[0xFF, byte]);
        prop_assert_eq!(TelegramRepr::parse_bytes(&bytes, Origin::Master), Ok(repr));
    }

    #[test]
    fn single_mdt_round_trips(
        address in drive_address(),
        word in any::<u16>(),
        service_info in any::<u16>(),
        data_block in proptest::collection::vec(any::<u8>(), 0..40),
    ) {
        let repr = TelegramRepr::Mdt(MdtRepr::Single {
            address,
            record: MdtRecordRepr { word: ControlWord::from_raw(word), service_info, data_block: &data_block },
        });
        let bytes = repr.to_vec();
        prop_assert_eq!(bytes.len(), 5 + data_block.len());
        prop_assert_eq!(TelegramRepr::parse_bytes(&bytes, Origin::Master), Ok(repr));
    }

    #[test]
    fn broadcast_mdt_round_trips(message_field in proptest::collection::vec(any::<u8>(), 4..80)) {
        let repr = TelegramRepr::Mdt(MdtRepr::Broadcast { message_field: &message_field });
        let bytes = repr.to_vec();
        prop_assert_eq!(bytes[0], 0xFF);
        prop_assert_eq!(TelegramRepr::parse_bytes(&bytes, Origin::Master), Ok(repr));
    }

    #[test]
    fn broadcast_records_round_trip(
        records in proptest::collection::vec((any::<u16>(), any::<u16>(), proptest::collection::vec(any::<u8>(), 0..6)), 1..6),
        gap in 0usize..4,
    ) {
        // Lay records one after another with `gap` spare bytes between them.
        let mut offsets = Vec::new();
        let mut end = 0;
        for (_, _, block) in &records {
            offsets.push(end);
            end += 4 + block.len() + gap;
        }
        let mut bytes = vec![0u8; 1 + end];
        bytes[0] = 0xFF;
        let mut packet = MdtPacket::new_checked(&mut bytes[..]).map_err(|e| TestCaseError::fail(e.to_string()))?;
        for ((word, info, block), offset) in records.iter().zip(&offsets) {
            let record = MdtRecordRepr { word: ControlWord::from_raw(*word), service_info: *info, data_block: block };
            prop_assert_eq!(packet.set_record_at(*offset, &record), Ok(()));
        }
        let repr = TelegramRepr::parse_bytes(&bytes, Origin::Master).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let TelegramRepr::Mdt(mdt) = repr else { return Err(TestCaseError::fail("not an MDT")) };
        for ((word, info, block), offset) in records.iter().zip(&offsets) {
            let record = mdt.record_at(*offset, block.len()).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(record.word.raw(), *word);
            prop_assert_eq!(record.service_info, *info);
            prop_assert_eq!(record.data_block, &block[..]);
        }
    }

    #[test]
    fn at_round_trips(
        address in drive_address(),
        word in any::<u16>(),
        service_info in any::<u16>(),
        data_block in proptest::collection::vec(any::<u8>(), 0..40),
    ) {
        let repr = TelegramRepr::At(AtRepr {
            address,
            record: AtRecordRepr { word: StatusWord::from_raw(word), service_info, data_block: &data_block },
        });
        let bytes = repr.to_vec();
        prop_assert_eq!(TelegramRepr::parse_bytes(&bytes, Origin::Slave), Ok(repr));
    }

    #[test]
    fn arbitrary_bytes_never_panic(
        bytes in proptest::collection::vec(any::<u8>(), 0..64),
        offset in any::<usize>(),
        small_offset in 0usize..70,
        len in any::<usize>(),
        small_len in 0usize..70,
    ) {
        for origin in [Origin::Master, Origin::Slave] {
            let _ = classify(&bytes, origin);
            if let Ok(repr) = TelegramRepr::parse_bytes(&bytes, origin) {
                // Whatever parses re-emits to the same bytes.
                prop_assert_eq!(repr.to_vec(), bytes.clone());
                let _ = repr.to_string_lossy();
                if let TelegramRepr::Mdt(mdt) = repr {
                    let _ = mdt.record_at(offset, len);
                    let _ = mdt.record_at(small_offset, small_len);
                }
            }
        }
        let _ = MstPacket::new_checked(&bytes[..]).map(|p| (p.phase(), MstRepr::parse(&p)));
        let mst = MstPacket::new_unchecked(&bytes[..]);
        let _ = (mst.address(), mst.phase_byte(), mst.phase());
        let mdt = MdtPacket::new_unchecked(&bytes[..]);
        let _ = (mdt.address(), mdt.record(), mdt.record_at(offset, len), mdt.record_at(small_offset, small_len));
        let _ = MdtRepr::parse(&mdt);
        let at = AtPacket::new_unchecked(&bytes[..]);
        let _ = (at.address(), at.status_word(), at.service_info(), at.data_block(), AtRepr::parse(&at));
        let record = DataRecord::new_unchecked(&bytes[..]);
        let _ = (record.word(), record.service_info(), record.data_block());
        let _ = DataRecordRepr::<u16>::parse(&record);
        let mut copy = bytes.clone();
        let mut mdt = MdtPacket::new_unchecked(&mut copy[..]);
        if let Ok(mut r) = mdt.record_at_mut(small_offset, small_len) {
            r.set_service_info(1);
            r.set_control_word(ControlWord::from_raw(2));
        }
    }
}

/// A tiny helper so the no-panic test also exercises Display of every parsed kind.
trait ToStringLossy {
    fn to_string_lossy(&self) -> String;
}

impl ToStringLossy for TelegramRepr<'_> {
    fn to_string_lossy(&self) -> String {
        match self {
            TelegramRepr::Mst(mst) => mst.to_string(),
            TelegramRepr::Mdt(MdtRepr::Single { record, .. }) => record.word.to_string(),
            TelegramRepr::Mdt(MdtRepr::Broadcast { message_field }) => format!("{message_field:?}"),
            TelegramRepr::At(at) => at.record.word.to_string(),
        }
    }
}
