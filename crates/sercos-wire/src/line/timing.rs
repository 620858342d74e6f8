//! Exact telegram durations on the line.

use crate::time::{BitRate, Duration};

/// Duration of `line_bits` bit times at `rate`, e.g. of [`frame_bit_len`](super::frame_bit_len)
/// bits for one telegram (exact in picoseconds; saturates).
pub const fn frame_duration(line_bits: u64, rate: BitRate) -> Duration {
    rate.duration_of_bits(line_bits)
}
