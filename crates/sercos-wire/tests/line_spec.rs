//! Line coding rules, one test per rule, each naming its source.
#![allow(clippy::unwrap_used)] // in tests a panic is a failure report

mod line_common;

use line_common::{CONFIGS, data_to_line, decode_chunked, frame_data_bits};
use sercos_wire::line::{
    self, BitSink, BitVec, BitWriter, Bits, Coding, Decoder, EncodeError, Encoder, LineConfig,
    LineError, MAX_FRAME_BYTES, MAX_TELEGRAM_BYTES, OwnedDecoded, Polarity, frame_bit_len,
    frame_duration,
};
use sercos_wire::time::BitRate;

const NRZ_PLAIN: LineConfig = LineConfig::new(Coding::Nrz, Polarity::LightOnHigh);

fn bits_of(v: &BitVec) -> Vec<bool> {
    v.bits().iter().collect()
}

fn str_bits(s: &str) -> Vec<bool> {
    s.chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| c == '1')
        .collect()
}

fn decode_data(data: &[bool]) -> Vec<OwnedDecoded> {
    let line = data_to_line(data, NRZ_PLAIN);
    decode_chunked(line.bits(), NRZ_PLAIN, &[usize::MAX])
}

// ERRATA, Telegrams, FCS: CRC-16/IBM-SDLC, check value 906EH for ASCII "123456789".
#[test]
fn fcs_check_value() {
    assert_eq!(line::fcs(b"123456789"), 0x906E);
    assert_eq!(line::reference::fcs(b"123456789"), 0x906E);
}

// ERRATA, Telegrams: flag 7EH, ADR, data, FCS low byte first, flag; bytes LSB first.
#[test]
fn mst_frame_layout() {
    let telegram = [0xFF, 0x02]; // MST, phase 2
    let fcs = line::fcs(&telegram).to_le_bytes();
    let mut out = BitVec::new();
    Encoder::new(NRZ_PLAIN).encode(&telegram, &mut out).unwrap();
    let mut expected = str_bits("01111110");
    let mut ones = 0;
    for byte in [0xFF, 0x02, fcs[0], fcs[1]] {
        for i in 0..8 {
            let bit = (byte >> i) & 1 == 1;
            expected.push(bit);
            ones = if bit { ones + 1 } else { 0 };
            if ones == 5 {
                expected.push(false);
                ones = 0;
            }
        }
    }
    expected.extend(str_bits("01111110"));
    assert_eq!(bits_of(&out), expected);
    // ADR FFH alone needs a 0 after its first five 1s.
    assert_eq!(&bits_of(&out)[8..17], &str_bits("11111 0 111")[..]);
}

// ERRATA, Telegrams: a 0 is inserted after five consecutive 1s, also across byte borders.
#[test]
fn zero_insertion_across_bytes() {
    // 0xF0 then 0x01, LSB first: 0000 1111 | 1000 0000 → 1s run of five across the border.
    let data = frame_data_bits(&[0xF0, 0x01]);
    assert_eq!(&data[8..25], &str_bits("00001111 1 0 0000000")[..]);
}

// ERRATA, Telegrams / captures README: NRZI, a 0 is a change of level, a 1 no change.
#[test]
fn nrzi_zero_toggles_one_holds() {
    let config = LineConfig::new(Coding::Nrzi, Polarity::LightOnHigh);
    let mut out = BitVec::new();
    let mut enc = Encoder::new(config);
    enc.idle(6, &mut out).unwrap();
    // Dark line (light on high → dark = 0), then six 0s: 1 0 1 0 1 0.
    assert_eq!(bits_of(&out), str_bits("101010"));
    out.clear();
    enc.encode(&[0xFF, 0x00], &mut out).unwrap();
    // Opening flag 01111110 after level 0: toggle to 1, hold six bits, toggle to 0.
    assert_eq!(&bits_of(&out)[..8], &str_bits("11111110")[..]);
}

// 410B §4.1 1H.7/1H.9 POLRXD/POLTXD: the reset value 0 means light on when the pin is 0;
// NRZ (RXDNRZ = 1, pin TxDNRZ) sends a 1 as light on.
#[test]
fn polarity_inverts_nrz_pins() {
    let mut low = BitVec::new();
    let mut high = BitVec::new();
    let t = [7, 1, 2, 3];
    Encoder::new(LineConfig::new(Coding::Nrz, Polarity::LightOnLow))
        .encode(&t, &mut low)
        .unwrap();
    Encoder::new(NRZ_PLAIN).encode(&t, &mut high).unwrap();
    let inverted: Vec<bool> = bits_of(&high).iter().map(|b| !b).collect();
    assert_eq!(bits_of(&low), inverted);
    assert_eq!(&bits_of(&high)[..8], &str_bits("01111110")[..]);
}

// Idle filler (docs/spec-notes.md, Line coding): data 0s, a square wave in NRZI; the level
// carries across filler and telegrams.
#[test]
fn idle_filler_is_a_square_wave_and_keeps_the_level() {
    let config = LineConfig::RESET;
    let mut out = BitVec::new();
    let mut enc = Encoder::new(config);
    enc.idle(100, &mut out).unwrap();
    let b = bits_of(&out);
    assert!(b.windows(2).all(|w| w[0] != w[1]));
    assert_eq!(enc.level(), *b.last().unwrap());
    let start = out.len();
    let n = enc.encode(&[1, 2, 3, 4, 5], &mut out).unwrap();
    let decoded = line::decode_all(out.bits(), config);
    assert_eq!(
        decoded,
        vec![OwnedDecoded::Telegram {
            start,
            end: start + n,
            bytes: vec![1, 2, 3, 4, 5]
        }]
    );
}

// Exact telegram duration: frame_bit_len counts flags and inserted 0s; 16 Mbit/s = 62.5 ns.
#[test]
fn frame_bit_len_and_duration() {
    // MST: 8 + (2 bytes + FCS, stuffing) + 8. FFH has one inserted 0.
    let mst = [0xFF, 0x00];
    let mut out = BitVec::new();
    let n = Encoder::new(LineConfig::RESET)
        .encode(&mst, &mut out)
        .unwrap();
    assert_eq!(n, frame_bit_len(&mst));
    assert_eq!(n, out.len());
    assert!(n > 16 + 32);
    assert_eq!(frame_duration(n, BitRate::Mbit16).as_picos(), n * 62_500);
    assert_eq!(frame_duration(n, BitRate::Mbit2).as_picos(), n * 500_000);
    assert_eq!(BitRate::Mbit4.bit_time().as_picos(), 250_000);
    assert_eq!(BitRate::Mbit8.bit_time().as_picos(), 125_000);
    // All 1s: a 0 after every five 1s.
    let ones = [0xFF; 10];
    let fcs = line::fcs(&ones).to_le_bytes();
    let mut expected = 16 + 96;
    let mut run = 0;
    for byte in ones.iter().chain(fcs.iter()) {
        for i in 0..8 {
            run = if (byte >> i) & 1 == 1 { run + 1 } else { 0 };
            if run == 5 {
                expected += 1;
                run = 0;
            }
        }
    }
    assert_eq!(frame_bit_len(&ones), expected);
}

// ERRATA, Telegrams: an ADR is always present; the limit is MAX_TELEGRAM_BYTES.
#[test]
fn encoder_rejects_empty_and_too_long() {
    let mut out = BitVec::new();
    let mut enc = Encoder::new(LineConfig::RESET);
    assert_eq!(enc.encode(&[], &mut out), Err(EncodeError::Empty));
    let long = vec![0u8; MAX_TELEGRAM_BYTES + 1];
    assert!(matches!(
        enc.encode(&long, &mut out),
        Err(EncodeError::TooLong { .. })
    ));
    assert!(out.is_empty());
    let longest = vec![0xA5u8; MAX_TELEGRAM_BYTES];
    let n = enc.encode(&longest, &mut out).unwrap();
    let d = line::decode_all(out.bits(), LineConfig::RESET);
    assert_eq!(
        d,
        vec![OwnedDecoded::Telegram {
            start: 0,
            end: n,
            bytes: longest
        }]
    );
}

// A caller's buffer that is too small: nothing written, level unchanged.
#[test]
fn bit_writer_full_writes_nothing() {
    let mut buf = [0u8; 4];
    let mut w = BitWriter::new(&mut buf);
    let mut enc = Encoder::new(LineConfig::RESET);
    enc.idle(3, &mut w).unwrap();
    let level = enc.level();
    let err = enc.encode(&[1, 2, 3], &mut w).unwrap_err();
    assert!(matches!(err, EncodeError::SinkFull(_)));
    assert_eq!(w.bit_len(), 3);
    assert_eq!(enc.level(), level);
}

// HDLC framing (ERRATA, Telegrams): the FCS is checked; a mismatch keeps the bytes.
#[test]
fn fcs_mismatch_keeps_the_bytes() {
    let mut data = frame_data_bits(&[0x05, 0x10, 0x20]);
    data[8 + 8] = !data[8 + 8]; // first data bit (no stuffing in ADR 05H)
    let d = decode_data(&data);
    let end = data.len() as u64;
    match &d[..] {
        [
            OwnedDecoded::Error {
                error:
                    LineError::FcsMismatch {
                        start: 0, end: e, ..
                    },
                received,
            },
        ] => {
            assert_eq!(*e, end);
            assert_eq!(received, &vec![0x05, 0x11, 0x20]);
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(!d[0].fcs_ok());
}

// Abort: seven 1s inside a frame; the decoder resynchronises on the next flag.
#[test]
fn abort_then_resynchronise() {
    let mut data = str_bits("0000 01111110 10100100 1111111 0000");
    let abort_at = 4 + 8 + 8 + 6;
    let next = data.len() as u64;
    data.extend(frame_data_bits(&[9, 8, 7]));
    let d = decode_data(&data);
    assert_eq!(d.len(), 2);
    assert_eq!(
        d[0],
        OwnedDecoded::Error {
            error: LineError::Abort {
                start: 4,
                at: abort_at
            },
            received: vec![0x25],
        }
    );
    assert_eq!(
        d[1],
        OwnedDecoded::Telegram {
            start: next,
            end: data.len() as u64,
            bytes: vec![9, 8, 7]
        }
    );
}

// Too short (docs/spec-notes.md: fewer than ADR + FCS = 24 bits) and not whole bytes.
#[test]
fn too_short_and_not_whole_bytes() {
    let mut data = str_bits("00 01111110 10101010 10101010 01111110");
    data.extend(str_bits("0000000 1111111 0")); // noise: ignored
    let second = data.len() as u64;
    data.extend(str_bits("01111110 1010101010101010101010101 01111110"));
    let d = decode_data(&data);
    assert_eq!(
        d,
        vec![
            OwnedDecoded::Error {
                error: LineError::TooShort {
                    start: 2,
                    end: 2 + 32,
                    bits: 16
                },
                received: vec![0x55, 0x55],
            },
            OwnedDecoded::Error {
                error: LineError::NotWholeBytes {
                    start: second,
                    end: second + 41,
                    bits: 25
                },
                received: vec![0x55, 0x55, 0x55],
            },
        ]
    );
}

// Frames longer than MAX_FRAME_BYTES are reported and the decoder recovers.
#[test]
fn too_long_then_resynchronise() {
    let mut data = str_bits("01111110");
    for _ in 0..(MAX_FRAME_BYTES + 2) {
        data.extend(str_bits("10000000"));
    }
    let next = data.len() as u64;
    data.extend(frame_data_bits(&[1, 2, 3]));
    let d = decode_data(&data);
    assert_eq!(d.len(), 2);
    assert!(matches!(
        d[0],
        OwnedDecoded::Error {
            error: LineError::TooLong { start: 0, .. },
            ..
        }
    ));
    assert_eq!(
        d[1],
        OwnedDecoded::Telegram {
            start: next,
            end: data.len() as u64,
            bytes: vec![1, 2, 3]
        }
    );
}

// Captures README: arbitrary bits between a closing flag and the next opening flag are noise.
#[test]
fn noise_between_telegrams_is_ignored() {
    let mut data = frame_data_bits(&[1, 0x40, 0x41]);
    let noise = str_bits("1101 0011 1110 1011 0000 1111 1110 0101 1");
    data.extend(&noise);
    let second = data.len() as u64;
    data.extend(frame_data_bits(&[2, 0x50]));
    let mut decoder = Decoder::new(NRZ_PLAIN);
    let line = data_to_line(&data, NRZ_PLAIN);
    let mut seen = Vec::new();
    decoder.push(line.bits(), |d| seen.push(d.to_owned()));
    assert_eq!(seen.len(), 2);
    assert_eq!(
        seen[1].clone(),
        OwnedDecoded::Telegram {
            start: second,
            end: data.len() as u64,
            bytes: vec![2, 0x50]
        }
    );
    assert_eq!(decoder.ignored(), 1);
}

// Chunks of any size give the same result as one chunk, for every configuration.
#[test]
fn one_bit_chunks_equal_one_chunk() {
    for config in CONFIGS {
        let mut out = BitVec::new();
        let mut enc = Encoder::new(config);
        for t in [
            &[255u8, 3][..],
            &[255, 0, 1, 2, 3, 4, 5, 6, 7],
            &[4, 0xFF, 0xFF, 0x7E],
        ] {
            enc.encode(t, &mut out).unwrap();
            enc.idle(13, &mut out).unwrap();
        }
        let whole = decode_chunked(out.bits(), config, &[usize::MAX]);
        assert_eq!(whole.len(), 3);
        assert_eq!(decode_chunked(out.bits(), config, &[1]), whole);
        assert_eq!(decode_chunked(out.bits(), config, &[3, 8, 17]), whole);
    }
}

// Bits views: a slice starting mid-byte reads the right bits; bad lengths are refused.
#[test]
fn bits_views() {
    let bytes = [0b1010_0000, 0xFF];
    assert!(Bits::new(&bytes, 17).is_none());
    let b = Bits::new(&bytes, 12).unwrap();
    let s = b.slice(2, 10).unwrap();
    assert_eq!(s.iter().collect::<Vec<_>>(), str_bits("10000011"));
    assert!(b.slice(5, 13).is_none());
    assert_eq!(b.get(12), None);
}

// ERRATA, Telegrams (HDLC framing): a frame is open from its opening flag to its closing flag
// or an abort; the decoder tells where an open frame with data began and its bytes so far, so
// that a receiver can take a telegram's start (its address) before its end has come.
#[test]
fn a_frame_in_progress_is_known_from_its_first_data_bit_to_its_end() {
    let mut line = BitVec::new();
    Encoder::new(NRZ_PLAIN)
        .encode(&[0x01, 0x42, 0x43], &mut line)
        .unwrap();
    let n = line.len() as usize;
    let mut d = Decoder::new(NRZ_PLAIN);
    assert_eq!(d.frame_in_progress(), None);
    // The opening flag alone: no data yet.
    d.push(line.bits().slice(0, 8).unwrap(), |_| {});
    assert!(d.in_frame());
    assert_eq!(d.frame_in_progress(), None);
    // The address and a bit more: its start and the address.
    d.push(line.bits().slice(8, 18).unwrap(), |_| {});
    assert_eq!(d.frame_in_progress(), Some((0, &[0x01][..])));
    // Everything but the closing flag's last bit: data and FCS bytes, no frame yet.
    let mut got = Vec::new();
    d.push(line.bits().slice(18, n - 1).unwrap(), |f| {
        got.push(f.fcs_ok())
    });
    assert!(got.is_empty());
    let (start, bytes) = d.frame_in_progress().unwrap();
    assert_eq!((start, &bytes[..3]), (0, &[0x01, 0x42, 0x43][..]));
    // The last bit closes it: the flag may open the next frame, which has no data yet.
    d.push(line.bits().slice(n - 1, n).unwrap(), |f| {
        got.push(f.fcs_ok())
    });
    assert_eq!(got, vec![true]);
    assert_eq!(d.frame_in_progress(), None);
    // An abort (seven 1s) ends a frame in progress as well.
    let mut d = Decoder::new(NRZ_PLAIN);
    d.push(line.bits().slice(0, 20).unwrap(), |_| {});
    assert!(d.frame_in_progress().is_some());
    d.push(data_to_line(&[true; 8], NRZ_PLAIN).bits(), |_| {});
    assert_eq!(d.frame_in_progress(), None);
}
