//! Helpers shared by the line-coding tests.
#![allow(dead_code)]

use sercos_wire::line::{
    BitSink, BitVec, Bits, Coding, Decoder, LineConfig, OwnedDecoded, Polarity, reference,
};

/// All four combinations of coding and polarity.
pub const CONFIGS: [LineConfig; 4] = [
    LineConfig::new(Coding::Nrzi, Polarity::LightOnLow),
    LineConfig::new(Coding::Nrzi, Polarity::LightOnHigh),
    LineConfig::new(Coding::Nrz, Polarity::LightOnLow),
    LineConfig::new(Coding::Nrz, Polarity::LightOnHigh),
];

/// Feeds `bits` to the fast decoder in chunks whose sizes cycle through `sizes` (0 = 1).
pub fn decode_chunked(bits: Bits<'_>, config: LineConfig, sizes: &[usize]) -> Vec<OwnedDecoded> {
    let mut out = Vec::new();
    let mut decoder = Decoder::new(config);
    let mut at = 0;
    let mut k = 0;
    while at < bits.len() {
        let size = sizes
            .get(k % sizes.len().max(1))
            .copied()
            .unwrap_or(1)
            .max(1);
        let to = (at + size).min(bits.len());
        decoder.push(bits.slice(at, to).expect("in range"), |d| {
            out.push(d.to_owned())
        });
        at = to;
        k += 1;
    }
    assert_eq!(decoder.position(), bits.len() as u64);
    out
}

/// Feeds `bits` to the reference decoder in chunks.
pub fn reference_chunked(bits: Bits<'_>, config: LineConfig, sizes: &[usize]) -> Vec<OwnedDecoded> {
    let mut out = Vec::new();
    let mut decoder = reference::Decoder::new(config);
    let mut at = 0;
    let mut k = 0;
    while at < bits.len() {
        let size = sizes
            .get(k % sizes.len().max(1))
            .copied()
            .unwrap_or(1)
            .max(1);
        let to = (at + size).min(bits.len());
        decoder.push(bits.slice(at, to).expect("in range"), |d| out.push(d));
        at = to;
        k += 1;
    }
    out
}

/// Codes data bits (already framed and stuffed) onto the line, one bit at a time, starting from
/// a dark line: NRZI 0 = change of level; NRZ 1 = light on.
pub fn data_to_line(data: &[bool], config: LineConfig) -> BitVec {
    let on = config.polarity.light_on_level();
    let mut level = !on;
    let mut out = BitVec::new();
    for &d in data {
        level = match config.coding {
            Coding::Nrzi => level ^ !d,
            Coding::Nrz => {
                if d {
                    on
                } else {
                    !on
                }
            }
        };
        out.push(level);
    }
    out
}

/// Data bits of a frame for `telegram` written by the reference rules: with the NRZ,
/// light-on-high configuration the line bits are the data bits.
pub fn frame_data_bits(telegram: &[u8]) -> Vec<bool> {
    let mut v = BitVec::new();
    reference::Encoder::new(LineConfig::new(Coding::Nrz, Polarity::LightOnHigh))
        .encode(telegram, &mut v)
        .expect("encodable");
    v.bits().iter().collect()
}

/// Appends `bits` to a vector of bools.
pub fn bools(bits: Bits<'_>) -> Vec<bool> {
    bits.iter().collect()
}

/// Length of a sink, for symmetry in tests.
pub fn len_of<S: BitSink>(s: &S) -> u64 {
    s.bit_len()
}
