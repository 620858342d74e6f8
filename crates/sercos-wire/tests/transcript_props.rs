//! The service transcript (`sercon capture transcript`, `sercon ring --transcript`) from any
//! sequence of master telegrams, the bytes of a damaged or foreign capture included: no
//! panic, and every entry points at a telegram it was given (sercos-telegrams.md, MDT
//! control word bits 5–0; `service_transcript` module docs).

use proptest::prelude::*;
use sercos_wire::service_transcript::{ServiceOp, TranscriptBuilder};

/// One telegram of the master: an MST (ADR 255, one byte), a unicast MDT record (ADR 1–4,
/// control word, service info, some data), a broadcast MDT or any bytes at all.
fn telegram() -> impl Strategy<Value = Vec<u8>> {
    let record = (
        1u8..=4,
        any::<u16>(),
        any::<u16>(),
        proptest::collection::vec(any::<u8>(), 0..8),
    )
        .prop_map(|(adr, control, info, data)| {
            let mut t = vec![adr];
            t.extend_from_slice(&control.to_le_bytes());
            t.extend_from_slice(&info.to_le_bytes());
            t.extend(data);
            t
        });
    prop_oneof![
        1 => any::<u8>().prop_map(|phase| vec![255, phase]),
        3 => record,
        1 => proptest::collection::vec(any::<u8>(), 0..40).prop_map(|mut t| {
            t.insert(0, 255);
            t
        }),
        1 => proptest::collection::vec(any::<u8>(), 0..12),
    ]
}

proptest! {
    #[test]
    fn any_master_telegrams_give_a_transcript_of_those_telegrams(
        telegrams in proptest::collection::vec(telegram(), 0..200)
    ) {
        let mut builder = TranscriptBuilder::new();
        let mut entries = Vec::new();
        for (i, t) in telegrams.iter().enumerate() {
            builder.master_telegram(t, i as u64);
            prop_assert!(builder.phase() <= 7);
            if i % 17 == 0 {
                entries.extend(builder.take_entries());
            }
        }
        entries.extend(builder.finish());
        for e in &entries {
            prop_assert!(e.first_telegram < telegrams.len() as u64, "{e:?}");
            prop_assert!((1..=254).contains(&e.drive), "{e:?}");
            prop_assert!(e.phase <= 7, "{e:?}");
            // Words come one per step, written steps only.
            prop_assert!(e.words.len() as u64 <= u64::from(e.steps), "{e:?}");
            if matches!(e.op, ServiceOp::Open) {
                prop_assert!(e.words.is_empty(), "{e:?}");
            }
        }
    }
}
