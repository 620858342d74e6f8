//! Simulated time: integer picoseconds.
//!
//! One bit at 16 Mbit/s lasts 62.5 ns, which is not a whole number of nanoseconds, so every
//! component of sercon counts time in picoseconds (DESIGN.md, "Time is injected, never read").
//! A `u64` of picoseconds spans more than 200 days of simulated time.

use core::fmt;
use core::ops::{Add, AddAssign, Sub, SubAssign};

/// A span of simulated time in picoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Duration(u64);

/// A point in simulated time: picoseconds since the start of the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Instant(u64);

impl Duration {
    /// No time at all.
    pub const ZERO: Duration = Duration(0);
    /// The longest representable span.
    pub const MAX: Duration = Duration(u64::MAX);

    /// A duration of `ps` picoseconds.
    pub const fn from_picos(ps: u64) -> Self {
        Duration(ps)
    }
    /// A duration of `ns` nanoseconds (saturating).
    pub const fn from_nanos(ns: u64) -> Self {
        Duration(ns.saturating_mul(1_000))
    }
    /// A duration of `us` microseconds (saturating).
    pub const fn from_micros(us: u64) -> Self {
        Duration(us.saturating_mul(1_000_000))
    }
    /// A duration of `ms` milliseconds (saturating).
    pub const fn from_millis(ms: u64) -> Self {
        Duration(ms.saturating_mul(1_000_000_000))
    }
    /// A duration of `s` seconds (saturating).
    pub const fn from_secs(s: u64) -> Self {
        Duration(s.saturating_mul(1_000_000_000_000))
    }
    /// The span in picoseconds.
    pub const fn as_picos(self) -> u64 {
        self.0
    }
    /// The span in whole nanoseconds (truncated).
    pub const fn as_nanos(self) -> u64 {
        self.0 / 1_000
    }
    /// The span in whole microseconds (truncated).
    pub const fn as_micros(self) -> u64 {
        self.0 / 1_000_000
    }
    /// The span in seconds as a float, for reports.
    pub fn as_secs_f64(self) -> f64 {
        self.0 as f64 / 1e12
    }
    /// `self * n`, saturating at [`Duration::MAX`].
    pub const fn saturating_mul(self, n: u64) -> Self {
        Duration(self.0.saturating_mul(n))
    }
    /// `self + rhs`, saturating at [`Duration::MAX`].
    pub const fn saturating_add(self, rhs: Duration) -> Self {
        Duration(self.0.saturating_add(rhs.0))
    }
    /// `self - rhs`, or zero if `rhs` is longer.
    pub const fn saturating_sub(self, rhs: Duration) -> Self {
        Duration(self.0.saturating_sub(rhs.0))
    }
    /// `self + rhs`, or `None` on overflow.
    pub const fn checked_add(self, rhs: Duration) -> Option<Self> {
        match self.0.checked_add(rhs.0) {
            Some(v) => Some(Duration(v)),
            None => None,
        }
    }
}

impl Instant {
    /// The start of the simulation.
    pub const ZERO: Instant = Instant(0);
    /// The end of representable time; used as "never" by `next_deadline`-style APIs.
    pub const MAX: Instant = Instant(u64::MAX);

    /// The instant `ps` picoseconds after the start.
    pub const fn from_picos(ps: u64) -> Self {
        Instant(ps)
    }
    /// Picoseconds since the start.
    pub const fn as_picos(self) -> u64 {
        self.0
    }
    /// Time elapsed since the start of the simulation.
    pub const fn since_start(self) -> Duration {
        Duration(self.0)
    }
    /// `self - earlier`, or zero if `earlier` is later.
    pub const fn saturating_duration_since(self, earlier: Instant) -> Duration {
        Duration(self.0.saturating_sub(earlier.0))
    }
    /// `self + d`, saturating at [`Instant::MAX`].
    pub const fn saturating_add(self, d: Duration) -> Self {
        Instant(self.0.saturating_add(d.0))
    }
    /// `self + d`, or `None` on overflow.
    pub const fn checked_add(self, d: Duration) -> Option<Self> {
        match self.0.checked_add(d.0) {
            Some(v) => Some(Instant(v)),
            None => None,
        }
    }
}

impl Add for Duration {
    type Output = Duration;
    /// Saturating addition (time never wraps).
    fn add(self, rhs: Duration) -> Duration {
        self.saturating_add(rhs)
    }
}
impl AddAssign for Duration {
    fn add_assign(&mut self, rhs: Duration) {
        *self = *self + rhs;
    }
}
impl Sub for Duration {
    type Output = Duration;
    /// Saturating subtraction (never below zero).
    fn sub(self, rhs: Duration) -> Duration {
        self.saturating_sub(rhs)
    }
}
impl SubAssign for Duration {
    fn sub_assign(&mut self, rhs: Duration) {
        *self = *self - rhs;
    }
}
impl Add<Duration> for Instant {
    type Output = Instant;
    /// Saturating addition (time never wraps).
    fn add(self, rhs: Duration) -> Instant {
        self.saturating_add(rhs)
    }
}
impl AddAssign<Duration> for Instant {
    fn add_assign(&mut self, rhs: Duration) {
        *self = *self + rhs;
    }
}
impl Sub<Duration> for Instant {
    type Output = Instant;
    /// Saturating subtraction (never before the start).
    fn sub(self, rhs: Duration) -> Instant {
        Instant(self.0.saturating_sub(rhs.0))
    }
}
impl Sub for Instant {
    type Output = Duration;
    /// The span between two instants, zero if `rhs` is later.
    fn sub(self, rhs: Instant) -> Duration {
        self.saturating_duration_since(rhs)
    }
}

fn fmt_picos(ps: u64, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    if ps % 1_000_000 == 0 {
        write!(f, "{} µs", ps / 1_000_000)
    } else if ps % 1_000 == 0 {
        write!(f, "{} ns", ps / 1_000)
    } else {
        write!(f, "{} ps", ps)
    }
}

impl fmt::Display for Duration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt_picos(self.0, f)
    }
}
impl fmt::Display for Instant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("t=")?;
        fmt_picos(self.0, f)
    }
}

/// The bit rates of the serial interface: 2 and 4 Mbit/s on the SERCON410B, 2, 4, 8 and
/// 16 Mbit/s on the SERCON816 (816 §2.3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BitRate {
    /// 2 Mbit/s.
    Mbit2,
    /// 4 Mbit/s.
    Mbit4,
    /// 8 Mbit/s (SERCON816 only).
    Mbit8,
    /// 16 Mbit/s (SERCON816 only).
    Mbit16,
}

impl BitRate {
    /// All bit rates, slowest first.
    pub const ALL: [BitRate; 4] = [
        BitRate::Mbit2,
        BitRate::Mbit4,
        BitRate::Mbit8,
        BitRate::Mbit16,
    ];

    /// The rate for a number of Mbit/s (2, 4, 8 or 16).
    pub const fn from_mbit(mbit: u32) -> Option<BitRate> {
        match mbit {
            2 => Some(BitRate::Mbit2),
            4 => Some(BitRate::Mbit4),
            8 => Some(BitRate::Mbit8),
            16 => Some(BitRate::Mbit16),
            _ => None,
        }
    }
    /// Megabits per second.
    pub const fn mbit(self) -> u32 {
        match self {
            BitRate::Mbit2 => 2,
            BitRate::Mbit4 => 4,
            BitRate::Mbit8 => 8,
            BitRate::Mbit16 => 16,
        }
    }
    /// Bits per second.
    pub const fn bits_per_second(self) -> u64 {
        self.mbit() as u64 * 1_000_000
    }
    /// The duration of one bit (62.5 ns at 16 Mbit/s).
    pub const fn bit_time(self) -> Duration {
        Duration(1_000_000 / self.mbit() as u64)
    }
    /// The duration of `bits` line bits (saturating).
    pub const fn duration_of_bits(self, bits: u64) -> Duration {
        self.bit_time().saturating_mul(bits)
    }
    /// How many whole bits fit into `d`.
    pub const fn bits_in(self, d: Duration) -> u64 {
        d.as_picos() / self.bit_time().as_picos()
    }
}

impl fmt::Display for BitRate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} Mbit/s", self.mbit())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_times_are_exact_in_picoseconds() {
        // 816 §2.3.1: 2, 4, 8, 16 Mbit/s.
        assert_eq!(BitRate::Mbit2.bit_time(), Duration::from_nanos(500));
        assert_eq!(BitRate::Mbit4.bit_time(), Duration::from_nanos(250));
        assert_eq!(BitRate::Mbit8.bit_time(), Duration::from_nanos(125));
        assert_eq!(BitRate::Mbit16.bit_time(), Duration::from_picos(62_500));
        assert_eq!(
            BitRate::Mbit16.duration_of_bits(16),
            Duration::from_micros(1)
        );
        assert_eq!(BitRate::Mbit16.bits_in(Duration::from_micros(250)), 4000);
    }

    #[test]
    fn arithmetic_saturates() {
        assert_eq!(Instant::MAX + Duration::from_secs(1), Instant::MAX);
        assert_eq!(Instant::ZERO - Duration::from_secs(1), Instant::ZERO);
        assert_eq!(
            Instant::from_picos(5) - Instant::from_picos(9),
            Duration::ZERO
        );
        assert_eq!(Duration::from_micros(2).to_string(), "2 µs");
        assert_eq!(Duration::from_picos(62_500).to_string(), "62500 ps");
        assert_eq!(BitRate::from_mbit(3), None);
    }
}
