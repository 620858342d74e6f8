//! Property tests: arbitrary service-channel writes never panic and never corrupt the
//! database (sercos-facts.md, "Service channel errors": a refused write changes nothing).

use proptest::prelude::*;
use sercos_drive::database::IdnDatabase;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::telegram::CommunicationPhase;

fn any_idn(known: Vec<Idn>) -> impl Strategy<Value = Idn> {
    prop_oneof![
        3 => proptest::sample::select(known),
        1 => any::<u16>().prop_map(Idn::from_raw),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(512)))]

    #[test]
    fn arbitrary_writes_never_corrupt(
        writes in proptest::collection::vec(
            (any_idn(IdnDatabase::standard().parameters().map(|p| p.idn).collect()),
             0u8..8,
             prop_oneof![
                 proptest::collection::vec(any::<u16>(), 0..6),
                 // Plausible variable-length headers too.
                 (0u16..40, 0u16..40, proptest::collection::vec(any::<u16>(), 0..24))
                     .prop_map(|(c, m, rest)| [c, m].into_iter().chain(rest).collect()),
             ],
             0u8..5),
            1..24),
    ) {
        let mut db = IdnDatabase::standard();
        for (idn, element, words, phase) in writes {
            let phase = CommunicationPhase::ALL.get(usize::from(phase)).copied().unwrap_or_default();
            db.set_phase(phase);
            let element = Element::from_bits(element);
            let before = db.clone();
            let result = db.write(idn, element, &words);
            if result.is_err() {
                prop_assert_eq!(&before, &db, "a refused write changed the database");
            }
            // Every parameter's operation data still reads back and decodes by its attribute.
            for parameter in db.parameters() {
                prop_assert!(parameter.value().is_ok(), "{} corrupted", parameter.idn);
                for element in Element::ALL {
                    let _ = db.read(parameter.idn, element);
                }
            }
        }
    }
}
