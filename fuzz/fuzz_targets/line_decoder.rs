//! Fuzz target: the line decoder on arbitrary input, in arbitrary chunks, for every
//! configuration. It must never panic, and the fast decoder must agree with the bit-serial
//! reference (docs/fuzzing.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use sercos_wire::line::{Bits, Coding, Decoder, LineConfig, Polarity, reference};

fuzz_target!(|data: &[u8]| {
    // First byte: configuration and chunk size; the rest: the line signal.
    let Some((&head, signal)) = data.split_first() else {
        return;
    };
    let coding = if head & 1 == 0 {
        Coding::Nrzi
    } else {
        Coding::Nrz
    };
    let polarity = if head & 2 == 0 {
        Polarity::LightOnLow
    } else {
        Polarity::LightOnHigh
    };
    let config = LineConfig::new(coding, polarity);
    let chunk = usize::from(head >> 2) + 1;
    let cut = usize::from(head >> 5);
    let len = (signal.len() * 8).saturating_sub(cut);
    let Some(bits) = Bits::new(signal, len) else {
        return;
    };

    let mut fast = Vec::new();
    let mut decoder = Decoder::new(config);
    let mut at = 0;
    while at < bits.len() {
        let to = (at + chunk).min(bits.len());
        if let Some(part) = bits.slice(at, to) {
            decoder.push(part, |d| fast.push(d.to_owned()));
        }
        at = to;
    }
    let slow = reference::decode_all(bits, config);
    assert_eq!(fast, slow, "fast and reference decoders disagree");
});
