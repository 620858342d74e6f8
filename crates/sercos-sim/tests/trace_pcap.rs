//! pcap and pcapng captures: link type USER0, nanosecond timestamps, the pseudo-header of
//! `trace::link_header` (docs/spec-notes.md, "Traces") and the telegram bytes behind it.
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use pcap_file::DataLink;
use pcap_file::pcap::PcapReader;
use pcap_file::pcapng::{Block, PcapNgReader};
use proptest::prelude::*;
use sercos_sim::trace::link_header::{HEADER_LEN, LinkHeader, LinkHeaderError};
use sercos_sim::trace::{LineErrorKind, PcapNgTrace, PcapTrace, SegmentId, TraceRecord, TraceSink};
use sercos_wire::line::{LineError, fcs};
use sercos_wire::telegram::Origin;
use sercos_wire::time::{BitRate, Instant};

const MST: [u8; 2] = [0xFF, 0x03];
const AT: [u8; 5] = [9, 0x00, 0xC0, 0x00, 0x00];

#[test]
fn pcap_header_packets_and_pseudo_header() {
    let mut trace = PcapTrace::new(Vec::new(), Some(SegmentId(1))).unwrap();
    // 1 bit at 16 Mbit/s after 1 ms: 1 000 000 062 500 ps, not whole nanoseconds.
    let t = Instant::from_picos(1_000_062_500);
    trace
        .record(
            &TraceRecord::telegram(t, SegmentId(1), Origin::Master, &MST)
                .with_bit_rate(BitRate::Mbit16),
        )
        .unwrap();
    // Another segment: filtered out.
    trace
        .record(&TraceRecord::telegram(
            t,
            SegmentId(0),
            Origin::Master,
            &MST,
        ))
        .unwrap();
    let computed = fcs(&AT);
    trace
        .record(&TraceRecord::line_error(
            t,
            SegmentId(1),
            Origin::Slave,
            LineError::FcsMismatch {
                start: 0,
                end: 0,
                received: 0xBEEF,
                computed,
            },
            &AT,
        ))
        .unwrap();
    assert_eq!(trace.packets(), 2);
    let bytes = trace.finish().unwrap();

    let mut reader = PcapReader::new(bytes.as_slice()).unwrap();
    let header = reader.header();
    assert_eq!(header.datalink, DataLink::USER0);
    assert_eq!(header.ts_resolution, pcap_file::TsResolution::NanoSecond);

    let first = reader.next_packet().unwrap().unwrap();
    // Nanosecond timestamp: the picoseconds below a nanosecond are dropped.
    assert_eq!(first.timestamp.as_nanos(), 1_000_062);
    assert_eq!(first.data.len(), HEADER_LEN + MST.len());
    // The documented layout, byte by byte (little endian).
    let expected_fcs = fcs(&MST).to_le_bytes();
    let mut expected = vec![
        1,  // version
        24, // header length
        1,
        0,      // segment 1
        0b0110, // master, FCS ok, FCS fields valid
        0,      // no line error
        16,
        0, // 16 Mbit/s
        expected_fcs[0],
        expected_fcs[1],
        expected_fcs[0],
        expected_fcs[1],
        0,
        0,
        0,
        0, // reserved
    ];
    expected.extend_from_slice(&1_000_062_500u64.to_le_bytes());
    expected.extend_from_slice(&MST);
    assert_eq!(&first.data[..], &expected[..]);

    let second = reader.next_packet().unwrap().unwrap();
    let (header, payload) = LinkHeader::parse(&second.data).unwrap();
    assert_eq!(payload, AT);
    assert_eq!(header.segment, SegmentId(1));
    assert_eq!(header.origin, Origin::Slave);
    assert!(!header.fcs_ok);
    assert_eq!(header.fcs, Some((0xBEEF, computed)));
    assert_eq!(header.line_error, Some(LineErrorKind::FcsMismatch));
    assert_eq!(header.bit_rate, None);
    assert_eq!(header.time, t);
    assert!(reader.next_packet().is_none());
}

#[test]
fn pcapng_has_one_interface_per_segment() {
    let mut trace = PcapNgTrace::new(Vec::new(), None).unwrap();
    for (i, segment) in [3u16, 5, 3].into_iter().enumerate() {
        trace
            .record(
                &TraceRecord::telegram(
                    Instant::from_picos(1_000 * i as u64 + 1_000),
                    SegmentId(segment),
                    Origin::Master,
                    &MST,
                )
                .with_bit_rate(BitRate::Mbit4),
            )
            .unwrap();
    }
    let bytes = trace.finish().unwrap();
    let mut reader = PcapNgReader::new(bytes.as_slice()).unwrap();
    let mut interfaces = 0;
    let mut packets = Vec::new();
    while let Some(block) = reader.next_block() {
        match block.unwrap() {
            Block::InterfaceDescription(idb) => {
                assert_eq!(idb.linktype, DataLink::USER0);
                interfaces += 1;
            }
            Block::EnhancedPacket(epb) => {
                let (header, payload) = LinkHeader::parse(&epb.data).unwrap();
                assert_eq!(payload, MST);
                packets.push((epb.interface_id, header.segment.0, epb.timestamp.as_nanos()));
            }
            _ => {}
        }
    }
    assert_eq!(interfaces, 2);
    assert_eq!(packets, [(0, 3, 1), (1, 5, 2), (0, 3, 3)]);
}

#[test]
fn broken_frames_carry_their_kind_and_no_fcs() {
    for (error, kind) in [
        (LineError::Abort { start: 0, at: 9 }, LineErrorKind::Abort),
        (
            LineError::TooShort {
                start: 0,
                end: 9,
                bits: 8,
            },
            LineErrorKind::TooShort,
        ),
        (
            LineError::NotWholeBytes {
                start: 0,
                end: 9,
                bits: 9,
            },
            LineErrorKind::NotWholeBytes,
        ),
        (
            LineError::TooLong { start: 0, at: 9 },
            LineErrorKind::TooLong,
        ),
    ] {
        let record =
            TraceRecord::line_error(Instant::ZERO, SegmentId(0), Origin::Master, error, &[1]);
        let header = LinkHeader::of(&record);
        let bytes = header.to_bytes();
        assert_eq!(bytes[4], 0b1000, "line error flag only");
        assert_eq!(bytes[5], kind.code());
        assert_eq!(LinkHeader::parse(&bytes).unwrap().0, header);
    }
}

#[test]
fn short_or_unknown_headers_are_errors() {
    assert_eq!(
        LinkHeader::parse(&[1; 10]),
        Err(LinkHeaderError::Truncated {
            needed: 24,
            got: 10
        })
    );
    let mut bytes = [0u8; 24];
    bytes[0] = 2;
    assert_eq!(LinkHeader::parse(&bytes), Err(LinkHeaderError::Version(2)));
    bytes[0] = 1;
    bytes[5] = 6;
    assert_eq!(
        LinkHeader::parse(&bytes),
        Err(LinkHeaderError::LineErrorCode(6))
    );
    // A longer header (a later version's extension) is skipped by its length field.
    let mut long = vec![0u8; 30];
    long[0] = 1;
    long[1] = 28;
    assert_eq!(LinkHeader::parse(&long).unwrap().1, [0, 0]);
}

proptest! {
    /// Any header survives to_bytes / parse, and parse never panics on any bytes.
    #[test]
    fn header_round_trip(
        segment in any::<u16>(),
        slave in any::<bool>(),
        time in any::<u64>(),
        rate in 0usize..5,
        error in 0u8..6,
        fcs_pair in any::<Option<(u16, u16)>>(),
    ) {
        let header = LinkHeader {
            segment: SegmentId(segment),
            origin: if slave { Origin::Slave } else { Origin::Master },
            fcs_ok: error == 0,
            fcs: fcs_pair,
            line_error: LineErrorKind::from_code(error),
            bit_rate: BitRate::ALL.get(rate).copied(),
            time: Instant::from_picos(time),
        };
        let mut packet = header.to_bytes().to_vec();
        packet.extend_from_slice(&[0xFF, 0x04]);
        let (parsed, payload) = LinkHeader::parse(&packet).unwrap();
        prop_assert_eq!(parsed, header);
        prop_assert_eq!(payload, &[0xFF, 0x04]);
    }

    #[test]
    fn parse_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..64)) {
        let _ = LinkHeader::parse(&bytes);
    }
}
