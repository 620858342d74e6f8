//! IDN and address text forms and conversions (sercos-facts.md, IDNs; sercos-telegrams.md, ADR).

use proptest::prelude::*;
use sercos_wire::address::{Address, AddressError, DriveAddress};
use sercos_wire::idn::{Element, Idn, IdnKind, IdnParseError};

fn parse(text: &str) -> Result<Idn, IdnParseError> {
    text.parse()
}

#[test]
fn examples_parse_and_format() {
    // sercos-facts.md, IDNs: "Written `S-0-0001`, `P-0-0019`"; bit 15 = S/P, 14–12 set,
    // 11–0 number.
    let cases: [(&str, u16, &str); 7] = [
        ("S-0-0001", 0x0001, "S-0-0001"),
        ("P-0-0019", 0x8013, "P-0-0019"),
        ("P-3-0123", 0x8000 | (3 << 12) | 123, "P-3-0123"),
        ("S-7-4095", 0x7FFF, "S-7-4095"),
        ("P-7-4095", 0xFFFF, "P-7-4095"),
        ("S-0-9", 9, "S-0-0009"),
        ("s-1-127", (1 << 12) | 127, "S-1-0127"),
    ];
    for (text, raw, shown) in cases {
        let idn = parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(idn.raw(), raw, "{text}");
        assert_eq!(idn.to_string(), shown, "{text}");
    }
    assert_eq!(Idn::from_raw(0).to_string(), "S-0-0000");
    assert_eq!(Idn::MDT_RECORD_POSITION.to_string(), "S-0-0009");
    assert_eq!(Idn::PHASE_3_TRANSITION_CHECK.to_string(), "S-0-0127");
    assert_eq!(format!("{:?}", Idn::from_raw(0x8013)), "Idn(P-0-0019)");
}

#[test]
fn bad_inputs_say_what_is_wrong() {
    use IdnParseError::*;
    let cases: [(&str, IdnParseError); 17] = [
        ("", Empty),
        ("X-0-0001", BadPrefix { found: 'X' }),
        ("Ä-0-0001", BadPrefix { found: 'Ä' }),
        (" S-0-0001", BadPrefix { found: ' ' }),
        ("S", MissingSeparator { position: 1 }),
        ("S0-0001", MissingSeparator { position: 1 }),
        ("S-0", MissingSeparator { position: 3 }),
        ("S-0+0001", MissingSeparator { position: 3 }),
        ("S--0001", BadParameterSet { position: 2 }),
        ("S-10-0001", BadParameterSet { position: 2 }),
        ("S-8-0001", ParameterSetOutOfRange(8)),
        ("S-9-1", ParameterSetOutOfRange(9)),
        ("S-0-", MissingNumber { position: 4 }),
        ("S-0-+1", MissingNumber { position: 4 }),
        ("S-0-00001", NumberTooLong),
        ("S-0-4096", NumberOutOfRange(4096)),
        ("S-0-0001 ", TrailingText { position: 8 }),
    ];
    for (text, error) in cases {
        assert_eq!(parse(text), Err(error), "{text:?}");
    }
    assert_eq!(parse("P-0-9999"), Err(NumberOutOfRange(9999)));
    assert_eq!(parse("S-0-12x"), Err(TrailingText { position: 6 }));
    assert_eq!(
        NumberOutOfRange(4096).to_string(),
        "data block number 4096 is out of range (0-4095)"
    );
    assert_eq!(
        BadPrefix { found: 'X' }.to_string(),
        "bad prefix 'X': an IDN starts with S or P"
    );
}

#[test]
fn every_u16_is_an_idn_and_round_trips_through_text() {
    // sercos-facts.md, IDNs: all 16 bits are S/P, set and number, so every u16 is an IDN.
    for raw in 0..=u16::MAX {
        let idn = Idn::from(raw);
        let text = idn.to_string();
        assert_eq!(text.len(), 8, "{text}");
        assert_eq!(parse(&text).map(u16::from), Ok(raw), "{text}");
        let rebuilt = Idn::new(idn.kind(), idn.parameter_set(), idn.number());
        assert_eq!(rebuilt, Ok(idn));
    }
}

proptest! {
    #[test]
    fn idn_u16_text_u16_round_trip(raw in any::<u16>()) {
        // sercos-facts.md, IDNs.
        let text = Idn::from_raw(raw).to_string();
        prop_assert_eq!(text.parse::<Idn>().map(Idn::raw), Ok(raw));
    }

    #[test]
    fn unpadded_numbers_parse(kind in prop_oneof![Just('S'), Just('P')], set in 0u8..=7, number in 0u16..=4095) {
        let text = format!("{kind}-{set}-{number}");
        let idn: Idn = text.parse().map_err(|e| TestCaseError::fail(format!("{text}: {e}")))?;
        prop_assert_eq!(idn.kind(), if kind == 'S' { IdnKind::Standard } else { IdnKind::Product });
        prop_assert_eq!(idn.parameter_set(), set);
        prop_assert_eq!(idn.number(), number);
    }

    #[test]
    fn arbitrary_text_never_panics(text in ".{0,12}") {
        let _ = text.parse::<Idn>();
    }
}

#[test]
fn element_names_and_bits() {
    // sercos-telegrams.md, MDT control word bits 5–3; sercos-facts.md, IDNs: 0 = service
    // channel closed, 1 IDN, 2 name, 3 attribute, 4 unit, 5 minimum, 6 maximum, 7 operation data.
    let expected = [
        (0, Element::ServiceChannelClosed),
        (1, Element::Idn),
        (2, Element::Name),
        (3, Element::Attribute),
        (4, Element::Unit),
        (5, Element::Minimum),
        (6, Element::Maximum),
        (7, Element::OperationData),
    ];
    for (bits, element) in expected {
        assert_eq!(Element::from_bits(bits), element);
        assert_eq!(u8::from(element), bits);
    }
    assert_eq!(
        Element::from_bits(0b1111_1010),
        Element::Name,
        "high bits ignored"
    );
    assert!(Element::try_from(8).is_err());
    assert_eq!(Element::OperationData.to_string(), "operation data");
}

#[test]
fn address_display_and_conversions() {
    // sercos-telegrams.md, ADR; ERRATA.md, Telegrams: 0 no station, 1–254 drives, 255 broadcast.
    assert_eq!(Address::from(0).to_string(), "0 (no station)");
    assert_eq!(Address::from(7).to_string(), "7");
    assert_eq!(Address::from(255).to_string(), "255 (broadcast)");
    assert_eq!(DriveAddress::try_from(0), Err(AddressError::NoStation));
    assert_eq!(
        DriveAddress::try_from(Address::Broadcast),
        Err(AddressError::Broadcast)
    );
    let drive = DriveAddress::new(254).expect("254 is a drive");
    assert_eq!(Address::from(drive), Address::Drive(drive));
    assert_eq!(u8::from(Address::from(drive)), 254);
    assert_eq!(DriveAddress::MIN.get(), 1);
    assert_eq!(DriveAddress::MAX.get(), 254);
}
