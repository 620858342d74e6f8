//! Exact telegram durations on the line.

/// Bit rates of the SERCOS II line (DESIGN: 2, 4, 8 and 16 Mbit/s).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BitRate {
    /// 2 Mbit/s: 500 ns per bit.
    Mbit2,
    /// 4 Mbit/s: 250 ns per bit.
    Mbit4,
    /// 8 Mbit/s: 125 ns per bit.
    Mbit8,
    /// 16 Mbit/s: 62.5 ns per bit.
    Mbit16,
}

impl BitRate {
    /// Bits per second.
    pub const fn bits_per_second(self) -> u64 {
        match self {
            BitRate::Mbit2 => 2_000_000,
            BitRate::Mbit4 => 4_000_000,
            BitRate::Mbit8 => 8_000_000,
            BitRate::Mbit16 => 16_000_000,
        }
    }

    /// One bit time in picoseconds (exact at every rate: 62.5 ns = 62 500 ps).
    pub const fn bit_time_ps(self) -> u64 {
        1_000_000_000_000 / self.bits_per_second()
    }
}

/// Duration in picoseconds of `line_bits` bit times at `rate`, e.g. of
/// [`frame_bit_len`](super::frame_bit_len) bits for one telegram. Saturates at `u64::MAX`.
pub const fn frame_duration_ps(line_bits: u64, rate: BitRate) -> u64 {
    line_bits.saturating_mul(rate.bit_time_ps())
}
