//! Line coding speed: encode and decode of realistic telegrams, single and as a stream.
//! Throughput is in line bits (flags and inserted 0s included).
//!
//! Run: `cargo bench -p sercos-wire --bench line`

#![allow(missing_docs)] // criterion_group! generates undocumented functions

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use sercos_wire::line::{BitVec, Decoder, Encoder, LineConfig, frame_bit_len, reference};

/// MST: ADR 255, phase 4.
fn mst() -> Vec<u8> {
    vec![255, 0x04]
}

/// AT: ADR, status word, service info, 8 data bytes.
fn at() -> Vec<u8> {
    let mut t = vec![3, 0x08, 0x00, 0x34, 0x12];
    t.extend((0..8u8).map(|i| i.wrapping_mul(37).wrapping_add(11)));
    t
}

/// Broadcast MDT for 32 drives: 32 records of control word, service info, 4 command bytes.
fn mdt32() -> Vec<u8> {
    let mut t = vec![255];
    for drive in 0..32u8 {
        t.extend([0x00, 0xE0, 0x00, 0x00]);
        t.extend((drive as u32 * 100_003).to_le_bytes());
    }
    t
}

/// A stream of `cycles` communication cycles: MST, broadcast MDT, 32 ATs, with 32 bits of
/// idle filler after every telegram.
fn stream(cycles: usize) -> (BitVec, u64) {
    let mut out = BitVec::new();
    let mut enc = Encoder::new(LineConfig::RESET);
    let mut count = 0;
    for _ in 0..cycles {
        for t in [mst(), mdt32()].into_iter().chain((1..=32).map(|a| {
            let mut t = at();
            t[0] = a;
            t
        })) {
            enc.encode(&t, &mut out).expect("encodable");
            enc.idle(32, &mut out).expect("grows");
            count += 1;
        }
    }
    (out, count)
}

fn single(c: &mut Criterion) {
    for (name, t) in [("mst", mst()), ("at8", at()), ("mdt32", mdt32())] {
        let bits = frame_bit_len(&t);
        let mut g = c.benchmark_group(format!("line/{name}"));
        g.throughput(Throughput::Elements(bits));

        let mut out = BitVec::with_capacity(bits as usize + 64);
        let mut enc = Encoder::new(LineConfig::RESET);
        g.bench_function("encode", |b| {
            b.iter(|| {
                out.clear();
                enc.encode(black_box(&t), &mut out).expect("encodable")
            })
        });
        let mut renc = reference::Encoder::new(LineConfig::RESET);
        g.bench_function("encode_reference", |b| {
            b.iter(|| {
                out.clear();
                renc.encode(black_box(&t), &mut out).expect("encodable")
            })
        });

        let mut frame = BitVec::new();
        Encoder::new(LineConfig::RESET)
            .encode(&t, &mut frame)
            .expect("encodable");
        let mut dec = Decoder::new(LineConfig::RESET);
        g.bench_function("decode", |b| {
            b.iter(|| {
                let mut n = 0usize;
                dec.push(black_box(frame.bits()), |d| n += usize::from(d.fcs_ok()));
                n
            })
        });
        let mut rdec = reference::Decoder::new(LineConfig::RESET);
        g.bench_function("decode_reference", |b| {
            b.iter(|| {
                let mut n = 0usize;
                rdec.push(black_box(frame.bits()), |d| n += usize::from(d.fcs_ok()));
                n
            })
        });
        g.finish();
    }
}

fn batch(c: &mut Criterion) {
    let cycles = 30;
    let (line, count) = stream(cycles);
    let mut g = c.benchmark_group("line/stream");
    g.throughput(Throughput::Elements(line.len()));
    g.sample_size(30);
    let telegrams: Vec<Vec<u8>> = [mst(), mdt32()]
        .into_iter()
        .chain((1..=32).map(|a| {
            let mut t = at();
            t[0] = a;
            t
        }))
        .collect();
    let mut out = BitVec::with_capacity(line.len() as usize + 64);
    g.bench_function("encode", |b| {
        b.iter(|| {
            out.clear();
            let mut enc = Encoder::new(LineConfig::RESET);
            for _ in 0..cycles {
                for t in &telegrams {
                    enc.encode(t, &mut out).expect("encodable");
                    enc.idle(32, &mut out).expect("grows");
                }
            }
            out.len()
        })
    });
    g.bench_function("encode_reference", |b| {
        b.iter(|| {
            out.clear();
            let mut enc = reference::Encoder::new(LineConfig::RESET);
            for _ in 0..cycles {
                for t in &telegrams {
                    enc.encode(t, &mut out).expect("encodable");
                    enc.idle(32, &mut out);
                }
            }
            out.len()
        })
    });
    g.bench_function("decode", |b| {
        b.iter(|| {
            let mut dec = Decoder::new(LineConfig::RESET);
            let mut n = 0u64;
            dec.push(black_box(line.bits()), |d| n += u64::from(d.fcs_ok()));
            assert_eq!(n, count);
            n
        })
    });
    g.bench_function("decode_reference", |b| {
        b.iter(|| {
            let mut dec = reference::Decoder::new(LineConfig::RESET);
            let mut n = 0u64;
            dec.push(black_box(line.bits()), |d| n += u64::from(d.fcs_ok()));
            assert_eq!(n, count);
            n
        })
    });
    g.finish();
}

criterion_group!(benches, single, batch);
criterion_main!(benches);
