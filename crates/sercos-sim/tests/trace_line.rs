//! From line bits to the telegram log: telegrams encoded by sercos-wire's line encoder,
//! decoded again (one with a flipped bit), logged through `TraceRecord::from_decoded`
//! (ERRATA, Telegrams: frame, FCS; sercos-telegrams.md, MST and AT).
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use sercos_sim::trace::{LogFormat, SegmentId, TelegramLog, TraceRecord, TraceSink};
use sercos_wire::line::{BitVec, Coding, Decoder, Encoder, LineConfig, Polarity, fcs};
use sercos_wire::telegram::Origin;
use sercos_wire::time::{BitRate, Instant};

const NRZ: LineConfig = LineConfig::new(Coding::Nrz, Polarity::LightOnHigh);
const MST: [u8; 2] = [0xFF, 0x04];
/// An AT from drive 3 with an all-zero record: no inserted 0s before the FCS.
const AT: [u8; 5] = [3, 0, 0, 0, 0];

#[test]
fn decoded_frames_are_logged_with_their_line_time_and_fcs_verdict() {
    let mut encoder = Encoder::new(NRZ);
    let mut line = BitVec::new();
    encoder.idle(16, &mut line).unwrap();
    encoder.encode(&MST, &mut line).unwrap();
    encoder.idle(16, &mut line).unwrap();
    let at_start = line.len();
    encoder.encode(&AT, &mut line).unwrap();
    encoder.idle(16, &mut line).unwrap();
    let bad_start = line.len();
    encoder.encode(&AT, &mut line).unwrap();
    encoder.idle(16, &mut line).unwrap();

    // Flip the first bit of the second AT's status word: opening flag (8) + ADR (8). With NRZ
    // coding one line bit is one data bit, so the AT arrives with status word 0001H.
    let flip = bad_start + 16;
    let mut corrupted = BitVec::new();
    for (i, bit) in line.bits().iter().enumerate() {
        corrupted.push(if i as u64 == flip { !bit } else { bit });
    }

    let rate = BitRate::Mbit4;
    let mut log = TelegramLog::new(Vec::new(), LogFormat::Text);
    let mut decoder = Decoder::new(NRZ);
    decoder.push(corrupted.bits(), |decoded| {
        let origin = if decoded.start() == 16 {
            Origin::Master
        } else {
            Origin::Slave
        };
        let time = Instant::ZERO.saturating_add(rate.duration_of_bits(decoded.start()));
        log.record(&TraceRecord::from_decoded(
            time,
            SegmentId(0),
            origin,
            &decoded,
        ))
        .unwrap();
    });
    let text = String::from_utf8(log.finish().unwrap()).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "{text}");

    // 250 ns per bit at 4 Mbit/s: the MST opens after 16 idle bits, at 4 µs.
    assert_eq!(
        lines[0],
        "0.000004000000 seg 0 master MST adr 255 phase 4 byte 04H len 2 fcs ok"
    );
    let at_time = at_start * 250_000;
    assert_eq!(
        lines[1],
        format!("0.{at_time:012} seg 0 slave AT adr 3 sw 0000H si 0000H len 5 fcs ok")
    );
    let bad_time = bad_start * 250_000;
    let received = fcs(&AT);
    let computed = fcs(&[3, 1, 0, 0, 0]);
    assert_eq!(
        lines[2],
        format!(
            "0.{bad_time:012} seg 0 slave AT adr 3 sw 0001H si 0000H len 5 fcs bad rx {received:04X}H calc {computed:04X}H error fcs-mismatch"
        )
    );
}
