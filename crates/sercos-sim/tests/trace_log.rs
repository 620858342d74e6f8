//! The telegram log: text and JSON lines for MST, MDT, AT, bad FCS and broken frames
//! (sercos-telegrams.md field layouts; ERRATA.md, Telegrams: FCS, little-endian words).
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use sercos_sim::trace::{LogFormat, SegmentId, TelegramLog, TraceRecord, TraceSink};
use sercos_wire::line::{LineError, fcs};
use sercos_wire::telegram::Origin;
use sercos_wire::time::{BitRate, Instant};

/// An AT from drive 3: status word C006H (ready to operate, error, busy), service info
/// 0042H, a two-byte data block (sercos-telegrams.md, Amplifier Telegram).
const AT: [u8; 7] = [3, 0x06, 0xC0, 0x42, 0x00, 0x11, 0x22];
/// A broadcast MDT whose first record has control word E000H and service info 1234H.
const MDT: [u8; 7] = [0xFF, 0x00, 0xE0, 0x34, 0x12, 0xAA, 0xBB];

fn records() -> Vec<TraceRecord<'static>> {
    let computed = fcs(&AT);
    vec![
        // sercos-telegrams.md, MST: ADR 255, phase 4 in bits 2-0; the other bits kept.
        TraceRecord::telegram(Instant::ZERO, SegmentId(0), Origin::Master, &[0xFF, 0xF4])
            .with_bit_rate(BitRate::Mbit2),
        TraceRecord::telegram(
            Instant::from_picos(62_500),
            SegmentId(1),
            Origin::Master,
            &MDT,
        ),
        TraceRecord::telegram(
            Instant::from_picos(1_500_000_000_001),
            SegmentId(1),
            Origin::Slave,
            &AT,
        ),
        TraceRecord::line_error(
            Instant::from_picos(2_000_000),
            SegmentId(1),
            Origin::Slave,
            LineError::FcsMismatch {
                start: 0,
                end: 90,
                received: computed ^ 1,
                computed,
            },
            &AT,
        ),
        TraceRecord::line_error(
            Instant::from_picos(3_000_000),
            SegmentId(4),
            Origin::Master,
            LineError::Abort { start: 0, at: 30 },
            &[0xFF, 0x01],
        ),
        // An MDT too short for its data record (needs ADR and 4 bytes).
        TraceRecord::telegram(
            Instant::from_picos(4_000_000),
            SegmentId(0),
            Origin::Master,
            &[5, 1, 2],
        ),
    ]
}

fn log(format: LogFormat) -> String {
    let mut log = TelegramLog::new(Vec::new(), format);
    for record in records() {
        log.record(&record).unwrap();
    }
    assert_eq!(log.lines(), records().len() as u64);
    String::from_utf8(log.finish().unwrap()).unwrap()
}

#[test]
fn text_lines() {
    let computed = fcs(&AT);
    let text = log(LogFormat::Text);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "0.000000000000 seg 0 master MST adr 255 phase 4 byte F4H len 2 fcs ok"
    );
    assert_eq!(
        lines[1],
        "0.000000062500 seg 1 master MDT adr 255 cw E000H si 1234H len 7 fcs ok"
    );
    assert_eq!(
        lines[2],
        "1.500000000001 seg 1 slave AT adr 3 sw C006H si 0042H len 7 fcs ok"
    );
    assert_eq!(
        lines[3],
        format!(
            "0.000002000000 seg 1 slave AT adr 3 sw C006H si 0042H len 7 fcs bad rx {:04X}H calc {computed:04X}H error fcs-mismatch",
            computed ^ 1
        )
    );
    assert_eq!(
        lines[4],
        "0.000003000000 seg 4 master - adr 255 broken len 2 fcs - error abort"
    );
    assert_eq!(
        lines[5],
        "0.000004000000 seg 0 master MDT adr 5 malformed len 3 fcs ok"
    );
    assert_eq!(lines.len(), 6);
}

#[test]
fn json_lines_parse_and_carry_the_fields() {
    let text = log(LogFormat::JsonLines);
    let values: Vec<serde_json::Value> = text
        .lines()
        .map(|line| serde_json::from_str(line).expect("valid JSON"))
        .collect();
    assert_eq!(values.len(), 6);
    let mst = &values[0];
    assert_eq!(mst["kind"], "MST");
    assert_eq!(mst["phase"], 4);
    assert_eq!(mst["phase_byte"], 0xF4);
    assert_eq!(mst["fcs"], "ok");
    assert_eq!(mst["line_error"], serde_json::Value::Null);
    let mdt = &values[1];
    assert_eq!(mdt["t_ps"], 62_500);
    assert_eq!(mdt["control_word"], 0xE000);
    assert_eq!(mdt["service_info"], 0x1234);
    let at = &values[2];
    assert_eq!(at["origin"], "slave");
    assert_eq!(at["adr"], 3);
    assert_eq!(at["status_word"], 0xC006);
    assert_eq!(at["t_ps"], 1_500_000_000_001u64);
    let bad = &values[3];
    assert_eq!(bad["fcs"], "bad");
    assert_eq!(bad["fcs_computed"], fcs(&AT));
    assert_eq!(bad["fcs_received"], fcs(&AT) ^ 1);
    assert_eq!(bad["line_error"], "fcs-mismatch");
    let broken = &values[4];
    assert_eq!(broken["kind"], serde_json::Value::Null);
    assert_eq!(broken["detail"], "broken");
    assert_eq!(broken["fcs"], "none");
    assert_eq!(broken["line_error"], "abort");
    assert_eq!(values[5]["detail"], "malformed");
    assert_eq!(values[2]["bytes"], "0306c042001122");
    assert_eq!(values[4]["bytes"], "ff01");
}

#[test]
fn json_keys_come_in_a_fixed_order() {
    let text = log(LogFormat::JsonLines);
    let first = text.lines().next().unwrap();
    assert!(
        first.starts_with(r#"{"t_ps":0,"segment":0,"origin":"master","kind":"MST","adr":255,"#),
        "{first}"
    );
}

#[test]
fn the_log_is_the_same_on_every_run() {
    assert_eq!(log(LogFormat::Text), log(LogFormat::Text));
    assert_eq!(log(LogFormat::JsonLines), log(LogFormat::JsonLines));
}

#[test]
fn an_empty_frame_is_logged_without_panicking() {
    let mut log = TelegramLog::new(Vec::new(), LogFormat::Text);
    log.record(&TraceRecord::line_error(
        Instant::ZERO,
        SegmentId(0),
        Origin::Slave,
        LineError::TooShort {
            start: 0,
            end: 16,
            bits: 0,
        },
        &[],
    ))
    .unwrap();
    log.record(&TraceRecord::telegram(
        Instant::ZERO,
        SegmentId(0),
        Origin::Slave,
        &[],
    ))
    .unwrap();
    let text = String::from_utf8(log.finish().unwrap()).unwrap();
    assert_eq!(
        text,
        "0.000000000000 seg 0 slave - broken len 0 fcs - error too-short\n\
         0.000000000000 seg 0 slave - malformed len 0 fcs ok\n"
    );
}

mod any_input {
    use proptest::prelude::*;
    use sercos_sim::trace::{LogFormat, SegmentId, TelegramLog, TraceRecord, TraceSink};
    use sercos_wire::line::LineError;
    use sercos_wire::telegram::Origin;
    use sercos_wire::time::Instant;

    fn error() -> impl Strategy<Value = Option<LineError>> {
        prop_oneof![
            Just(None),
            (any::<u16>(), any::<u16>()).prop_map(|(received, computed)| Some(
                LineError::FcsMismatch {
                    start: 0,
                    end: 0,
                    received,
                    computed
                }
            )),
            Just(Some(LineError::Abort { start: 0, at: 0 })),
            Just(Some(LineError::TooLong { start: 0, at: 0 })),
        ]
    }

    proptest! {
        /// Any bytes from either origin, good or in error, give exactly one line in each
        /// format, and the JSON line parses (no panics from input: PREAMBLE ground rules).
        #[test]
        fn any_record_gives_one_valid_line(
            bytes in prop::collection::vec(any::<u8>(), 0..40),
            slave in any::<bool>(),
            time in any::<u64>(),
            segment in any::<u16>(),
            error in error(),
        ) {
            let origin = if slave { Origin::Slave } else { Origin::Master };
            let record = match error {
                None => TraceRecord::telegram(Instant::from_picos(time), SegmentId(segment), origin, &bytes),
                Some(error) => TraceRecord::line_error(Instant::from_picos(time), SegmentId(segment), origin, error, &bytes),
            };
            for format in [LogFormat::Text, LogFormat::JsonLines] {
                let mut log = TelegramLog::new(Vec::new(), format);
                log.record(&record).unwrap();
                let text = String::from_utf8(log.finish().unwrap()).unwrap();
                prop_assert_eq!(text.matches('\n').count(), 1);
                prop_assert!(text.ends_with('\n'));
                if format == LogFormat::JsonLines {
                    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
                    prop_assert_eq!(value["t_ps"].as_u64(), Some(time));
                    prop_assert_eq!(value["len"].as_u64(), Some(bytes.len() as u64));
                }
            }
        }
    }
}
