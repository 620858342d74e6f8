//! The trace hash: SHA-256 of the text log (DESIGN.md, Principles: "The same configuration
//! and seed give byte-identical traces").
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use sercos_sim::trace::{
    LogFormat, SegmentId, TelegramLog, TraceHash, TraceHasher, TraceRecord, TraceSink,
};
use sercos_wire::telegram::Origin;
use sercos_wire::time::Instant;

fn feed<S: TraceSink>(sink: &mut S, phase: u8) {
    for i in 0..10u64 {
        sink.record(&TraceRecord::telegram(
            Instant::from_picos(i * 1_000_000),
            SegmentId(0),
            Origin::Master,
            &[0xFF, phase],
        ))
        .unwrap();
    }
}

#[test]
fn empty_trace_hash_is_sha256_of_nothing() {
    // FIPS 180-4 test vector: SHA-256 of the empty message.
    assert_eq!(
        TraceHasher::new().finish().to_string(),
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    );
}

#[test]
fn hash_equals_sha256_of_the_text_log() {
    let mut both = (
        TraceHasher::new(),
        TelegramLog::new(Vec::new(), LogFormat::Text),
    );
    feed(&mut both, 4);
    let (hasher, log) = both;
    assert_eq!(hasher.records(), 10);
    assert_eq!(hasher.hash(), hasher.clone().finish());
    assert_eq!(hasher.finish(), TraceHash::of_bytes(&log.into_inner()));
}

#[test]
fn same_records_same_hash_different_records_different_hash() {
    let run = |phase| {
        let mut hasher = TraceHasher::new();
        feed(&mut hasher, phase);
        hasher.finish()
    };
    assert_eq!(run(4), run(4));
    assert_ne!(run(4), run(3));
}
