//! The trace hash: SHA-256 over the records in capture form (DESIGN.md, Principles: "The
//! same configuration and seed give byte-identical traces").
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use sercos_sim::trace::link_header::LinkHeader;
use sercos_sim::trace::{SegmentId, TraceHash, TraceHasher, TraceRecord, TraceSink};
use sercos_wire::telegram::Origin;
use sercos_wire::time::{BitRate, Instant};
use sha2::{Digest, Sha256};

/// Ten ATs from drive 7 with `data` as their one-byte data block.
fn records(data: u8, at_ps: u64) -> Vec<(Instant, [u8; 6])> {
    (0..10u64)
        .map(|i| {
            (
                Instant::from_picos(i * 1_000_000 + at_ps),
                [7, 0x00, 0xC0, 0x00, 0x00, data],
            )
        })
        .collect()
}

fn hash(data: u8, at_ps: u64) -> TraceHash {
    let mut hasher = TraceHasher::new();
    for (time, bytes) in records(data, at_ps) {
        hasher
            .record(&TraceRecord::telegram(
                time,
                SegmentId(0),
                Origin::Slave,
                &bytes,
            ))
            .unwrap();
    }
    assert_eq!(hasher.records(), 10);
    assert_eq!(hasher.hash(), hasher.clone().finish());
    hasher.finish()
}

#[test]
fn empty_trace_hash_is_sha256_of_nothing() {
    // FIPS 180-4 test vector: SHA-256 of the empty message.
    assert_eq!(
        TraceHasher::new().finish().to_string(),
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    );
    assert_eq!(TraceHash::of_bytes(&[]), TraceHasher::new().finish());
}

#[test]
fn hash_covers_length_pseudo_header_and_bytes() {
    let record = TraceRecord::telegram(
        Instant::from_picos(5),
        SegmentId(3),
        Origin::Master,
        &[0xFF, 4],
    )
    .with_bit_rate(BitRate::Mbit8);
    let mut hasher = TraceHasher::new();
    hasher.record(&record).unwrap();
    let mut expected = Sha256::new();
    expected.update(26u32.to_le_bytes());
    expected.update(LinkHeader::of(&record).to_bytes());
    expected.update([0xFF, 4]);
    assert_eq!(hasher.finish().0, <[u8; 32]>::from(expected.finalize()));
}

#[test]
fn same_records_same_hash() {
    assert_eq!(hash(1, 0), hash(1, 0));
}

#[test]
fn one_data_byte_or_one_picosecond_changes_the_hash() {
    // Neither the data block nor sub-nanosecond times show in the text log; the hash sees both.
    assert_ne!(hash(1, 0), hash(2, 0));
    assert_ne!(hash(1, 0), hash(1, 1));
}
