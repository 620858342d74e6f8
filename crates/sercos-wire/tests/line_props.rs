//! Property tests: the fast coder equals the bit-serial reference, round trips hold, and
//! garbage never panics (DESIGN: fast path and reference path; ERRATA, Telegrams: frame, FCS).

mod line_common;

use line_common::{CONFIGS, data_to_line, decode_chunked, frame_data_bits, reference_chunked};
use proptest::prelude::*;
use sercos_wire::line::{
    self, BitSink, BitVec, BitWriter, Bits, Encoder, LineConfig, OwnedDecoded, frame_bit_len,
    reference,
};

fn config() -> impl Strategy<Value = LineConfig> {
    (0..4usize).prop_map(|i| CONFIGS[i])
}

/// Telegrams (ADR and data), each with the idle filler that follows it.
fn stream() -> impl Strategy<Value = Vec<(Vec<u8>, u64)>> {
    prop::collection::vec(
        (
            prop::collection::vec(any::<u8>(), 1..48),
            prop_oneof![Just(0u64), 0..64u64, Just(32u64)],
        ),
        1..6,
    )
}

fn chunks() -> impl Strategy<Value = Vec<usize>> {
    prop::collection::vec(prop_oneof![1..9usize, 1..200usize, Just(4096usize)], 1..8)
}

proptest! {
    // ERRATA, Telegrams: frame, zero insertion, FCS. Both encoders give the same line bits and
    // the count that frame_bit_len predicts, and the level carries over between telegrams.
    #[test]
    fn fast_encoder_equals_reference(config in config(), telegrams in stream()) {
        let mut fast = BitVec::new();
        let mut slow = BitVec::new();
        let mut fe = Encoder::new(config);
        let mut re = reference::Encoder::new(config);
        for (t, gap) in &telegrams {
            let n = fe.encode(t, &mut fast).expect("encodable");
            let m = re.encode(t, &mut slow).expect("encodable");
            prop_assert_eq!(n, m);
            prop_assert_eq!(n, frame_bit_len(t));
            fe.idle(*gap, &mut fast).expect("grows");
            re.idle(*gap, &mut slow);
            prop_assert_eq!(fe.level(), re.level());
        }
        prop_assert_eq!(fast.len(), slow.len());
        prop_assert_eq!(fast.bits(), slow.bits());
    }

    // Writing into a caller's buffer gives the same bits as the growable buffer.
    /// `BitVec::inverted` (a byte at a time) equals the bits inverted one by one, and
    /// keeps the padding 0 (equal vectors compare equal).
    #[test]
    fn inverted_equals_bit_by_bit(bits in proptest::collection::vec(any::<bool>(), 0..200)) {
        let mut v = BitVec::new();
        let mut inv = BitVec::new();
        for b in &bits {
            v.push(*b);
            inv.push(!*b);
        }
        prop_assert_eq!(v.inverted(), inv);
        prop_assert_eq!(v.inverted().inverted(), v);
    }

    /// `BitVec::from_bits` (a byte at a time) copies any slice of bits exactly, padding 0.
    #[test]
    fn from_bits_copies_any_slice(
        bits in proptest::collection::vec(any::<bool>(), 0..200),
        a in 0usize..200,
        b in 0usize..200,
    ) {
        let mut v = BitVec::new();
        for x in &bits {
            v.push(*x);
        }
        let (from, to) = (a.min(b).min(bits.len()), a.max(b).min(bits.len()));
        let slice = v.bits().slice(from, to).expect("in range");
        let mut want = BitVec::new();
        for x in &bits[from..to] {
            want.push(*x);
        }
        prop_assert_eq!(BitVec::from_bits(slice), want);
    }

    #[test]
    fn bit_writer_equals_bit_vec(config in config(), telegrams in stream()) {
        let mut vec = BitVec::new();
        let mut storage = vec![0u8; 8 * 1024];
        let mut writer = BitWriter::new(&mut storage);
        let mut a = Encoder::new(config);
        let mut b = Encoder::new(config);
        for (t, gap) in &telegrams {
            a.encode(t, &mut vec).expect("encodable");
            b.encode(t, &mut writer).expect("fits");
            a.idle(*gap, &mut vec).expect("grows");
            b.idle(*gap, &mut writer).expect("fits");
        }
        prop_assert_eq!(vec.len(), writer.bit_len());
        prop_assert_eq!(vec.bits(), writer.bits());
    }

    // decode(encode(x)) = x, with exact positions, at any chunking, fast and reference.
    #[test]
    fn round_trip_with_positions(config in config(), telegrams in stream(), sizes in chunks()) {
        let mut line = BitVec::new();
        let mut enc = Encoder::new(config);
        let mut expected = Vec::new();
        for (t, gap) in &telegrams {
            let start = line.len();
            let n = enc.encode(t, &mut line).expect("encodable");
            expected.push(OwnedDecoded::Telegram { start, end: start + n, bytes: t.clone() });
            enc.idle(*gap, &mut line).expect("grows");
        }
        prop_assert_eq!(&decode_chunked(line.bits(), config, &sizes), &expected);
        prop_assert_eq!(&reference_chunked(line.bits(), config, &sizes), &expected);
    }

    // Back-to-back telegrams sharing one flag: the closing flag of one opens the next.
    #[test]
    fn shared_flags(config in config(), telegrams in stream(), sizes in chunks()) {
        let mut data: Vec<bool> = Vec::new();
        let mut expected = Vec::new();
        for (t, _) in &telegrams {
            let frame = frame_data_bits(t);
            let start = data.len().saturating_sub(if data.is_empty() { 0 } else { 8 });
            if !data.is_empty() {
                data.truncate(data.len() - 8);
            }
            data.extend_from_slice(&frame);
            expected.push(OwnedDecoded::Telegram {
                start: start as u64,
                end: data.len() as u64,
                bytes: t.clone(),
            });
        }
        let line = data_to_line(&data, config);
        prop_assert_eq!(&decode_chunked(line.bits(), config, &sizes), &expected);
        prop_assert_eq!(&reference_chunked(line.bits(), config, &sizes), &expected);
    }

    // Corrupted streams: same telegrams, same positions, same errors in both decoders.
    #[test]
    fn corrupted_stream_fast_equals_reference(
        config in config(),
        telegrams in stream(),
        flips in prop::collection::vec(any::<prop::sample::Index>(), 0..6),
        sizes in chunks(),
    ) {
        let mut line = BitVec::new();
        let mut enc = Encoder::new(config);
        for (t, gap) in &telegrams {
            enc.encode(t, &mut line).expect("encodable");
            enc.idle(*gap, &mut line).expect("grows");
        }
        let mut bits: Vec<bool> = line.bits().iter().collect();
        for f in &flips {
            let i = f.index(bits.len());
            bits[i] = !bits[i];
        }
        let mut corrupted = BitVec::new();
        for b in bits {
            corrupted.push(b);
        }
        let fast = decode_chunked(corrupted.bits(), config, &sizes);
        let slow = reference_chunked(corrupted.bits(), config, &[usize::MAX]);
        prop_assert_eq!(fast, slow);
    }

    // Arbitrary garbage never panics either decoder, and they agree.
    #[test]
    fn garbage_fast_equals_reference(
        config in config(),
        bytes in prop::collection::vec(any::<u8>(), 0..600),
        cut in 0..8usize,
        sizes in chunks(),
    ) {
        let len = (bytes.len() * 8).saturating_sub(cut);
        let bits = Bits::new(&bytes, len).expect("in range");
        let fast = decode_chunked(bits, config, &sizes);
        let slow = reference_chunked(bits, config, &sizes);
        prop_assert_eq!(fast, slow);
    }

    // Garbage biased towards flags, runs of 1s and stuffing: exercises every error path.
    #[test]
    fn flag_rich_garbage_fast_equals_reference(
        config in config(),
        pieces in prop::collection::vec(
            prop_oneof![
                Just(0x7Eu8), Just(0xFF), Just(0x00), Just(0x3F), Just(0xFC), any::<u8>()
            ],
            0..400,
        ),
        sizes in chunks(),
    ) {
        let data: Vec<bool> = pieces
            .iter()
            .flat_map(|b| (0..8).rev().map(move |i| (b >> i) & 1 == 1))
            .collect();
        let line = data_to_line(&data, config);
        let fast = decode_chunked(line.bits(), config, &sizes);
        let slow = reference_chunked(line.bits(), config, &sizes);
        prop_assert_eq!(fast, slow);
    }

    // ERRATA, Telegrams: the FCS crate and the bit-serial reference FCS agree.
    #[test]
    fn fcs_equals_bit_serial_reference(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        prop_assert_eq!(line::fcs(&bytes), reference::fcs(&bytes));
    }
}
