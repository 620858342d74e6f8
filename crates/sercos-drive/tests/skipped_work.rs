//! Work the drive skips each cycle gives the same database as doing it: a second advance to
//! the same instant, a diagnostic message (S-0-0095, sercos-facts.md "IDNs") rewritten with
//! the text it already holds, fixed-length feedback encoded into the words held.

mod support;

use proptest::prelude::*;
use sercos_drive::database::IdnDatabase;
use sercos_drive::drive::EmulatedDrive;
use sercos_drive::parameter::Parameter;
use sercos_wire::attribute::Value;
use sercos_wire::idn::Idn;
use sercos_wire::telegram::ReadyToOperate;
use sercos_wire::time::{Duration, Instant};
use support::{idn, write};

const DIAGNOSTIC_MESSAGE: Idn = Idn::from_raw(95);

/// A drive in phase 4 with telegram type 2 (MDT S-0-0036, AT S-0-0040; Beckhoff AX2000,
/// IDN 15) and velocity control (S-0-0032 = 2).
fn phase_4_drive() -> EmulatedDrive {
    let mut drive = support::in_phase_2_with(&[("S-0-0015", &[2]), ("S-0-0032", &[2])]);
    support::step_to_phase_4(&mut drive);
    drive
}

fn snapshot(drive: &EmulatedDrive) -> (Vec<(Idn, Vec<u16>)>, u16, f64, f64) {
    (
        drive
            .database()
            .parameters()
            .map(|p| (p.idn, p.words().to_vec()))
            .collect(),
        drive.status_word().raw(),
        drive.axis().velocity_rpm(),
        drive.axis().position_deg(),
    )
}

#[test]
fn advancing_twice_to_one_instant_is_advancing_once() {
    let mut once = phase_4_drive();
    let mut now = Instant::ZERO;
    for step in 0..20 {
        now += Duration::from_micros(250);
        let control = if step < 10 { 0xE000 } else { 0xC000 };
        assert!(
            once.receive_mdt_record(now, &support::velocity_record(control, 5_000_000))
                .is_ok()
        );
        let mut twice = once.clone();
        once.advance_to(now);
        twice.advance_to(now);
        twice.advance_to(now);
        assert_eq!(snapshot(&once), snapshot(&twice), "step {step}");
    }
}

#[test]
fn a_write_between_two_advances_to_one_instant_is_taken() {
    let mut drive = phase_4_drive();
    let now = Instant::ZERO + Duration::from_millis(1);
    assert!(
        drive
            .receive_mdt_record(now, &support::velocity_record(0xE000, 0))
            .is_ok()
    );
    drive.advance_to(now);
    let before = drive.axis().command();
    // S-0-0036 in 4 decimal places: 100 rpm, written through the database at the same
    // instant; the next advance must follow it.
    write(&mut drive, "S-0-0036", &[0x4240, 0x000F]);
    drive.advance_to(now);
    assert_ne!(drive.axis().command(), before);
    // A control word without drive-on at the same instant: the status word follows too.
    assert!(
        drive
            .receive_mdt_record(now, &support::velocity_record(0x0000, 0))
            .is_ok()
    );
    drive.advance_to(now);
    assert_eq!(
        drive.status_word().ready_to_operate(),
        ReadyToOperate::PowerReady
    );
}

proptest! {
    /// S-0-0095 after any sequence of messages holds exactly the encoding of the last one
    /// (cut to the maximum length at a character boundary), as `set_value` gives it.
    #[test]
    fn diagnostic_message_words_are_the_encoding_of_the_last_text(
        texts in proptest::collection::vec("[a-zA-Z0-9 äß€]{0,70}", 1..6),
    ) {
        let mut database = IdnDatabase::standard();
        let Some(mut expected) = database.get(DIAGNOSTIC_MESSAGE).cloned() else {
            return Err(TestCaseError::fail("S-0-0095 missing"));
        };
        for text in &texts {
            database.set_diagnostic_message(text);
            database.set_diagnostic_message(text);
        }
        let last = texts.last().map(String::as_str).unwrap_or("");
        let mut end = last.len().min(usize::from(expected.max_len));
        while !last.is_char_boundary(end) {
            end -= 1;
        }
        prop_assert!(expected.set_value(&Value::Text(last.as_bytes()[..end].to_vec())).is_ok());
        prop_assert_eq!(
            database.get(DIAGNOSTIC_MESSAGE).map(Parameter::words),
            Some(expected.words())
        );
    }

    /// Fixed-length values encoded into the words held are the words `Attribute::encode`
    /// gives (or the same refusal).
    #[test]
    fn fixed_length_values_encode_as_attribute_encode(value in any::<i64>(), which in 0usize..4) {
        let name = ["S-0-0040", "S-0-0051", "S-0-0135", "P-0-0019"][which];
        let database = IdnDatabase::standard();
        let Some(mut parameter) = database.get(idn(name)).cloned() else {
            return Err(TestCaseError::fail(format!("{name} missing")));
        };
        let value = Value::Signed(value);
        let encoded = parameter.attribute.encode(&value, parameter.max_len);
        let before = parameter.words().to_vec();
        let result = parameter.set_value(&value);
        prop_assert_eq!(result.is_ok(), encoded.is_ok());
        match encoded {
            Ok(words) => prop_assert_eq!(parameter.words(), &words[..]),
            Err(_) => prop_assert_eq!(parameter.words(), &before[..]),
        }
    }
}

/// One step of a drive's life in phase 4.
#[derive(Debug, Clone)]
enum Step {
    /// An MDT record (control word, S-0-0036) `micros` later.
    Record {
        micros: u64,
        control: u16,
        velocity: i32,
    },
    /// A service-channel write of operation data (taken or refused alike by both drives).
    Write { name: &'static str, words: Vec<u16> },
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        4 => (1u64..2000, prop::sample::select(vec![0xE000u16, 0xC000, 0xE100, 0x6000, 0x0000]), -20_000_000i32..20_000_000)
            .prop_map(|(micros, control, velocity)| Step::Record { micros, control, velocity }),
        1 => (prop::sample::select(vec!["S-0-0032", "S-0-0033", "P-0-0001", "P-0-0003", "S-0-0036", "S-0-0099"]), 0u16..12)
            .prop_map(|(name, word)| Step::Write { name, words: vec![word] }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64)))]

    /// The command inputs and diagnostics the drive keeps between cycles give what reading
    /// the database afresh every cycle gives (sercos-telegrams.md control word bits 15-13,
    /// 9-8; sercos-facts.md "IDNs" S-0-0095, S-0-0135): a drive whose kept values are dropped
    /// before every step (a mutable access to the database) ends up the same.
    #[test]
    fn kept_inputs_and_diagnostics_are_what_a_fresh_read_gives(steps in proptest::collection::vec(step(), 1..40)) {
        let mut kept = phase_4_drive();
        let mut fresh = kept.clone();
        let mut now = Instant::ZERO;
        for (i, s) in steps.iter().enumerate() {
            let _ = fresh.database_mut();
            match s {
                Step::Record { micros, control, velocity } => {
                    now += Duration::from_micros(*micros);
                    let r = support::velocity_record(*control, *velocity);
                    prop_assert_eq!(kept.receive_mdt_record(now, &r).is_ok(), fresh.receive_mdt_record(now, &r).is_ok());
                }
                Step::Write { name, words } => {
                    let a = kept.database_mut().write(idn(name), sercos_wire::idn::Element::OperationData, words);
                    let b = fresh.database_mut().write(idn(name), sercos_wire::idn::Element::OperationData, words);
                    prop_assert_eq!(a, b);
                }
            }
            let _ = fresh.database_mut();
            kept.advance_to(now);
            fresh.advance_to(now);
            prop_assert_eq!(snapshot(&kept), snapshot(&fresh), "step {}: {:?}", i, s);
            prop_assert_eq!(kept.axis().command(), fresh.axis().command());
        }
    }
}
