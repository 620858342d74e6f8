//! The Wireshark dissector `contrib/wireshark/sercos2.lua` against a pcap written by
//! `PcapTrace`: tshark must decode the pseudo-header and the MST, MDT and AT fields of
//! sercos-telegrams.md.
//!
//! tshark is required: without it this test fails and says how to install it
//! (`apt-get install -y tshark`, see docs/traces.md).
// Test helpers may unwrap: a failure is the test failing.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

use sercos_sim::trace::{PcapNgTrace, PcapTrace, SegmentId, TraceRecord, TraceSink};
use sercos_wire::line::{LineError, fcs};
use sercos_wire::telegram::{ControlWord, Origin, ReadyToOperate, StatusWord};
use sercos_wire::time::{BitRate, Instant};

fn dissector() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../contrib/wireshark/sercos2.lua")
}

fn require_tshark() {
    match Command::new("tshark").arg("--version").output() {
        Ok(out) if out.status.success() => {}
        other => panic!(
            "tshark is needed by this test but did not run ({other:?}); install it with \
             `apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y tshark` \
             (see docs/traces.md)"
        ),
    }
}

/// Runs tshark with the dissector on `file`, printing `fields` one line per packet, and the
/// expert messages (`_ws.expert.message`) as one more, last column.
fn tshark_fields(file: &Path, prefs: &[&str], fields: &[&str]) -> Vec<Vec<String>> {
    require_tshark();
    let script = format!("lua_script:{}", dissector().display());
    let mut command = Command::new("tshark");
    command.args(["-n", "-r"]).arg(file).args(["-X", &script]);
    for pref in prefs {
        command.args(["-o", pref]);
    }
    command.args([
        "-T",
        "fields",
        "-E",
        "separator=;",
        "-E",
        "occurrence=a",
        "-E",
        "aggregator=|",
    ]);
    for field in fields {
        command.args(["-e", field]);
    }
    // One more column, always last: the expert messages, where a Lua error would show.
    command.args(["-e", "_ws.expert.message"]);
    let out = command.output().expect("tshark runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "tshark failed: {stderr}");
    assert!(
        !stderr.contains("Lua: Error") && !stderr.contains("lua_script"),
        "the dissector did not load: {stderr}"
    );
    String::from_utf8(out.stdout)
        .expect("tshark prints text")
        .lines()
        .map(|line| {
            let row: Vec<String> = line.split(';').map(str::to_owned).collect();
            let expert = row.last().cloned().unwrap_or_default();
            assert!(!expert.contains("Lua Error"), "dissector error: {expert}");
            row
        })
        .collect()
}

/// Four telegrams: an MST in phase 4, a broadcast MDT with two records, an AT with status
/// bits, and an AT whose FCS was corrupted on the line.
fn write_sample(path: &Path) -> (ControlWord, StatusWord, u16) {
    let mut trace = PcapTrace::new(Vec::new(), None).expect("pcap header");
    let seg = SegmentId(2);
    let t = |ns: u64| Instant::from_picos(ns * 1000 + 500);

    // sercos-telegrams.md, MST: ADR 255, phase byte bits 2-0 = 4.
    let mst = [0xFF, 0x04];
    trace
        .record(
            &TraceRecord::telegram(t(0), seg, Origin::Master, &mst).with_bit_rate(BitRate::Mbit4),
        )
        .unwrap();

    // sercos-telegrams.md, MDT control word: drive ON, enable, restart, element 7 (operation
    // data), write, MHS.
    let cw = ControlWord::from_raw(0xE000 | (7 << 3) | 0b11);
    let mut mdt = vec![0xFF];
    for (word, info, data) in [
        (cw.raw(), 0x1234u16, [0xAA, 0xBB]),
        (0x0001, 0x5678, [0xCC, 0xDD]),
    ] {
        mdt.extend_from_slice(&word.to_le_bytes());
        mdt.extend_from_slice(&info.to_le_bytes());
        mdt.extend_from_slice(&data);
    }
    trace
        .record(&TraceRecord::telegram(t(20_000), seg, Origin::Master, &mdt))
        .unwrap();

    // sercos-telegrams.md, AT status word: ready to operate (11), class 2 change bit, busy,
    // service channel error, AHS.
    let sw = StatusWord::new()
        .with_ready_to_operate(ReadyToOperate::from_bits(0b11))
        .with_change_bit_class_2(true)
        .with_busy(true)
        .with_service_channel_error(true)
        .with_ahs(true);
    let mut at = vec![3];
    at.extend_from_slice(&sw.raw().to_le_bytes());
    at.extend_from_slice(&0x0042u16.to_le_bytes());
    at.extend_from_slice(&[1, 2, 3, 4]);
    trace
        .record(&TraceRecord::telegram(t(40_000), seg, Origin::Slave, &at))
        .unwrap();

    // The same AT with a corrupted FCS (ERRATA, Telegrams: ISO/IEC 3309 FCS).
    let computed = fcs(&at);
    let received = computed ^ 0x0100;
    let error = LineError::FcsMismatch {
        start: 0,
        end: 100,
        received,
        computed,
    };
    trace
        .record(&TraceRecord::line_error(
            t(60_000),
            seg,
            Origin::Slave,
            error,
            &at,
        ))
        .unwrap();

    std::fs::write(path, trace.finish().unwrap()).expect("write pcap");
    (cw, sw, computed)
}

fn sample_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(name)
}

#[test]
fn tshark_decodes_pseudo_header_and_telegram_kinds() {
    let file = sample_file("trace_tshark_kinds.pcap");
    let (_, _, computed) = write_sample(&file);
    let rows = tshark_fields(
        &file,
        &[],
        &[
            "sercos2.segment",
            "sercos2.kind",
            "sercos2.adr",
            "sercos2.fcs_ok",
            "sercos2.line_error",
            "sercos2.time_ps",
            "sercos2.bit_rate",
            "sercos2.fcs_computed",
        ],
    );
    assert_eq!(rows.len(), 4, "{rows:?}");
    let kinds: Vec<&str> = rows.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(kinds, ["MST", "MDT", "AT", "AT"]);
    let adrs: Vec<&str> = rows.iter().map(|r| r[2].as_str()).collect();
    assert_eq!(adrs, ["255", "255", "3", "3"]);
    for row in &rows {
        assert_eq!(row[0], "2", "segment");
    }
    // The pseudo-header's FCS verdict: ok for three, bad (FCS mismatch, code 1) for the last.
    let fcs_ok: Vec<bool> = rows.iter().map(|r| r[3] == "1" || r[3] == "True").collect();
    assert_eq!(fcs_ok, [true, true, true, false], "{rows:?}");
    assert_eq!(rows[3][4], "1");
    assert_eq!(rows[0][4], "0");
    // Exact picoseconds survive in the pseudo-header.
    assert_eq!(rows[1][5], "20000500");
    assert_eq!(rows[0][6], "4");
    assert_eq!(
        u16::from_str_radix(rows[3][7].trim_start_matches("0x"), 16).unwrap(),
        computed
    );
}

#[test]
fn tshark_decodes_mst_phase() {
    let file = sample_file("trace_tshark_mst.pcap");
    write_sample(&file);
    let rows = tshark_fields(&file, &[], &["sercos2.mst.phase", "sercos2.mst.phase_byte"]);
    // sercos-telegrams.md, MST: bits 2-0 = phase 4.
    assert_eq!(rows[0][..2], ["4", "0x04"]);
    assert_eq!(rows[1][..2], ["", ""]);
}

#[test]
fn tshark_decodes_control_word_bits() {
    let file = sample_file("trace_tshark_cw.pcap");
    let (cw, _, _) = write_sample(&file);
    let rows = tshark_fields(
        &file,
        &[],
        &[
            "sercos2.mdt.cw",
            "sercos2.mdt.cw.drive_on",
            "sercos2.mdt.cw.drive_enable",
            "sercos2.mdt.cw.drive_restart",
            "sercos2.mdt.cw.element",
            "sercos2.mdt.cw.last",
            "sercos2.mdt.cw.write",
            "sercos2.mdt.cw.mhs",
            "sercos2.service_info",
        ],
    );
    let row = &rows[1];
    assert_eq!(row[0], format!("0x{:04x}", cw.raw()));
    let truthy = |s: &str| s == "1" || s == "True";
    assert!(
        truthy(&row[1]) && truthy(&row[2]) && truthy(&row[3]),
        "{row:?}"
    );
    assert_eq!(row[4], "7", "element 111 = operation data");
    assert!(!truthy(&row[5]), "bit 2 clear: transmission in progress");
    assert!(truthy(&row[6]), "bit 1 set: write");
    assert_eq!(row[7], "1", "MHS");
    // Without the block-length preference the broadcast MDT is one record.
    assert_eq!(row[8], "0x1234");
}

#[test]
fn tshark_splits_broadcast_mdt_with_block_length_preference() {
    let file = sample_file("trace_tshark_mdt_split.pcap");
    write_sample(&file);
    let rows = tshark_fields(
        &file,
        &["sercos2.mdt_block_len:2"],
        &[
            "sercos2.mdt.cw",
            "sercos2.service_info",
            "sercos2.data_block",
        ],
    );
    assert_eq!(rows[1][0], "0xe03b|0x0001");
    assert_eq!(rows[1][1], "0x1234|0x5678");
    assert_eq!(rows[1][2], "aabb|ccdd");
}

#[test]
fn tshark_decodes_status_word_bits_and_bad_fcs() {
    let file = sample_file("trace_tshark_sw.pcap");
    let (_, sw, _) = write_sample(&file);
    let rows = tshark_fields(
        &file,
        &[],
        &[
            "sercos2.at.sw",
            "sercos2.at.sw.ready",
            "sercos2.at.sw.change_class2",
            "sercos2.at.sw.change_class3",
            "sercos2.at.sw.busy",
            "sercos2.at.sw.error",
            "sercos2.at.sw.ahs",
            "sercos2.data_block",
        ],
    );
    let truthy = |s: &str| s == "1" || s == "True";
    for row in &rows[2..4] {
        assert_eq!(row[0], format!("0x{:04x}", sw.raw()));
        assert_eq!(row[1], "3", "ready to operate");
        assert!(truthy(&row[2]), "class 2 change bit");
        assert!(!truthy(&row[3]), "class 3 change bit");
        assert!(truthy(&row[4]) && truthy(&row[5]), "busy and error");
        assert_eq!(row[6], "1", "AHS");
        assert_eq!(row[7], "01020304");
    }
    assert!(!rows[2][8].contains("FCS mismatch"), "{:?}", rows[2]);
    assert!(rows[3][8].contains("FCS mismatch"), "{:?}", rows[3]);
}

#[test]
fn tshark_shows_broken_and_malformed_frames_without_lua_errors() {
    let file = sample_file("trace_tshark_broken.pcap");
    let mut trace = PcapTrace::new(Vec::new(), None).unwrap();
    // An aborted frame (seven 1s, ERRATA, Telegrams: frame): the bytes before the abort.
    trace
        .record(&TraceRecord::line_error(
            Instant::ZERO,
            SegmentId(0),
            Origin::Master,
            LineError::Abort { start: 0, at: 40 },
            &[0xFF, 0x12],
        ))
        .unwrap();
    // An MDT too short for a data record (sercos-telegrams.md, Data Record: 4 bytes at least).
    trace
        .record(&TraceRecord::telegram(
            Instant::from_picos(1_000_000),
            SegmentId(0),
            Origin::Master,
            &[4, 1, 2],
        ))
        .unwrap();
    std::fs::write(&file, trace.finish().unwrap()).unwrap();
    let rows = tshark_fields(
        &file,
        &[],
        &[
            "sercos2.line_error",
            "sercos2.kind",
            "sercos2.received",
            "sercos2.malformed",
        ],
    );
    assert_eq!(rows.len(), 2, "{rows:?}");
    assert_eq!(rows[0][0], "2", "abort");
    assert_eq!(rows[0][1], "", "a broken frame has no kind");
    assert_eq!(rows[0][2], "ff12");
    assert!(rows[0][4].contains("Frame broken"), "{:?}", rows[0]);
    assert_eq!(rows[1][1], "MDT");
    assert_eq!(rows[1][3], "0102");
}

#[test]
fn tshark_reads_pcapng_with_one_interface_per_segment() {
    let file = sample_file("trace_tshark_segments.pcapng");
    let mut trace = PcapNgTrace::new(Vec::new(), None).unwrap();
    // The MST passes segment 0, then segment 1 of the ring (sercos-telegrams.md, MST).
    for (ns, segment) in [(0u64, 0u16), (500, 1)] {
        trace
            .record(
                &TraceRecord::telegram(
                    Instant::from_picos(ns * 1000),
                    SegmentId(segment),
                    Origin::Master,
                    &[0xFF, 0x02],
                )
                .with_bit_rate(BitRate::Mbit16),
            )
            .unwrap();
    }
    std::fs::write(&file, trace.finish().unwrap()).unwrap();
    let rows = tshark_fields(
        &file,
        &[],
        &[
            "frame.interface_id",
            "sercos2.segment",
            "sercos2.mst.phase",
            "sercos2.bit_rate",
        ],
    );
    assert_eq!(rows.len(), 2, "{rows:?}");
    assert_eq!(rows[0][..4], ["0", "0", "2", "16"]);
    assert_eq!(rows[1][..4], ["1", "1", "2", "16"]);
}

/// Whatever a line carries, the dissector decodes it or marks it, never with a Lua error:
/// 400 random telegrams (any length, any bytes, from the master or a slave, with and without
/// a valid-looking ADR) and broken frames of every kind, read with and without the broadcast
/// MDT's block length (sercos-telegrams.md: MST, MDT, AT, Data Record).
#[test]
fn tshark_decodes_random_telegrams_without_lua_errors() {
    use rand_chacha::ChaCha8Rng;
    use rand_core::{RngCore, SeedableRng};
    let file = sample_file("trace_tshark_random.pcap");
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut trace = PcapTrace::new(Vec::new(), None).unwrap();
    let count: u32 = 400;
    for i in 0..count {
        // One in eight an MST's length (ADR 255 and one byte), else any length up to 59.
        let len = if i % 8 == 0 {
            2
        } else {
            (rng.next_u32() % 60) as usize
        };
        let mut bytes = vec![0u8; len];
        rng.fill_bytes(&mut bytes);
        // Every other one an MST's or a broadcast MDT's ADR, or a drive's.
        match (i % 4, bytes.first_mut()) {
            (0, Some(adr)) => *adr = 255,
            (1, Some(adr)) => *adr = (*adr % 254) + 1,
            _ => {}
        }
        let origin = if rng.next_u32() % 2 == 0 {
            Origin::Master
        } else {
            Origin::Slave
        };
        let at = Instant::from_picos(u64::from(i) * 1_000_000);
        let x = u64::from(rng.next_u32() % 1000);
        let record = match rng.next_u32() % 5 {
            0 => TraceRecord::line_error(
                at,
                SegmentId(0),
                origin,
                LineError::Abort {
                    start: x,
                    at: x + 9,
                },
                &bytes,
            ),
            1 => TraceRecord::line_error(
                at,
                SegmentId(0),
                origin,
                LineError::FcsMismatch {
                    start: x,
                    end: x + 8 * len as u64,
                    received: rng.next_u32() as u16,
                    computed: rng.next_u32() as u16,
                },
                &bytes,
            ),
            2 => TraceRecord::line_error(
                at,
                SegmentId(0),
                origin,
                LineError::TooShort {
                    start: x,
                    end: x + 9,
                    bits: 3,
                },
                &bytes,
            ),
            _ => TraceRecord::telegram(at, SegmentId(0), origin, &bytes),
        };
        trace.record(&record).unwrap();
    }
    std::fs::write(&file, trace.finish().unwrap()).unwrap();
    for prefs in [
        &[][..],
        &["sercos2.mdt_block_len:2"][..],
        &["sercos2.mdt_block_len:13"][..],
    ] {
        // `tshark_fields` fails on a Lua error in any row.
        let rows = tshark_fields(&file, prefs, &["sercos2.kind", "sercos2.malformed"]);
        assert_eq!(rows.len(), count as usize, "{prefs:?}");
        assert!(rows.iter().any(|r| r[0] == "MST"), "{prefs:?}");
        assert!(rows.iter().any(|r| r[0] == "AT"), "{prefs:?}");
    }
}
