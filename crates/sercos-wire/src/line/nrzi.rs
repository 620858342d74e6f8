//! Word-wide NRZI / NRZ conversion between data bits and pin levels.
//!
//! ERRATA, Telegrams and the captures: in NRZI a 0 is sent as a change of level and a 1 as no
//! change. Bits are in line order, the first bit in the most significant position.

use super::config::{Coding, LineConfig};

/// Pin levels for `n` (1..=32) data bits right-aligned in `data`, first bit most significant;
/// `level` is the pin level before the first bit and becomes the level after the last one.
pub(crate) fn encode_word(config: LineConfig, data: u32, n: u32, level: &mut bool) -> u32 {
    debug_assert!((1..=32).contains(&n));
    let pins = match config.coding {
        Coding::Nrzi => {
            // A 0 toggles: the level after bit i is the start level XOR the parity of the
            // toggles up to i, a prefix XOR from the most significant bit down.
            let mut t = (!data) << (32 - n);
            t ^= t >> 1;
            t ^= t >> 2;
            t ^= t >> 4;
            t ^= t >> 8;
            t ^= t >> 16;
            if *level {
                t = !t;
            }
            t >> (32 - n)
        }
        Coding::Nrz => {
            let mask = u32::from(config.polarity.nrz_mask()) * 0x0101_0101;
            (data ^ mask) & (u32::MAX >> (32 - n))
        }
    };
    *level = pins & 1 == 1;
    pins
}

/// Data bits of 8 pin levels (first bit most significant); `prev` is the pin level before
/// them and becomes the last of them.
#[inline]
pub(crate) fn decode_byte(config: LineConfig, pins: u8, prev: &mut bool) -> u8 {
    let d = match config.coding {
        Coding::Nrzi => !(pins ^ ((pins >> 1) | (u8::from(*prev) << 7))),
        Coding::Nrz => pins ^ config.polarity.nrz_mask(),
    };
    *prev = pins & 1 == 1;
    d
}

/// Data bit of one pin level; `prev` is the level before it and becomes this one.
#[inline]
pub(crate) fn decode_bit(config: LineConfig, pin: bool, prev: &mut bool) -> bool {
    let d = match config.coding {
        Coding::Nrzi => pin == *prev,
        Coding::Nrz => pin == config.polarity.light_on_level(),
    };
    *prev = pin;
    d
}
