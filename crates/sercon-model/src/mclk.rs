//! MCLK periods ("ticks") and their conversion to and from picosecond instants.
//!
//! 816 §2.4.1: "the telegram processing unit and all other part of the circuitry are
//! clocked by MCLK". Everything the model does happens on an MCLK edge; tick `k` is the
//! `k`-th rising edge after time 0, at `floor(k · 10¹² / f_MCLK)` picoseconds (exact for
//! 20 MHz and 32 MHz, never drifting for other frequencies).

use sercos_wire::time::Instant;

use crate::reciprocal::{Reciprocal, ShortDivision};

const PS_PER_S: u128 = 1_000_000_000_000;

/// Converts between MCLK ticks and instants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MclkClock {
    hz: u64,
    /// Picoseconds per tick when that is a whole number (the fast path), with its
    /// reciprocal (instants become ticks by a multiplication, not a division).
    ps_per_tick: Option<Reciprocal>,
    /// The division by that whole number for instants in its range (the first 47 days at
    /// 32 MHz): one product and a shift, no correction ([`ShortDivision::NONE`] for the
    /// other clocks).
    short: ShortDivision,
}

impl MclkClock {
    /// A clock of `hz` (clamped to 1 Hz ..= 1 THz).
    pub(crate) fn new(hz: u64) -> Self {
        let hz = hz.clamp(1, 1_000_000_000_000);
        let exact = (PS_PER_S % u128::from(hz) == 0)
            .then(|| Reciprocal::new((PS_PER_S / u128::from(hz)) as u64));
        MclkClock {
            hz,
            ps_per_tick: exact,
            short: exact.map_or(ShortDivision::NONE, |p| ShortDivision::new(p.divisor())),
        }
    }

    /// The instant of tick `k` (saturating at the end of representable time).
    pub(crate) fn instant(&self, k: u64) -> Instant {
        let ps = match self.ps_per_tick {
            // The fast path stays in 64 bits (a 128-bit product and division per call
            // showed up in the event loop's profile).
            Some(p) => return Instant::from_picos(k.saturating_mul(p.divisor())),
            None => u128::from(k) * PS_PER_S / u128::from(self.hz),
        };
        Instant::from_picos(u64::try_from(ps).unwrap_or(u64::MAX))
    }

    /// The last tick at or before `t`.
    #[inline]
    pub(crate) fn tick_at_or_before(&self, t: Instant) -> u64 {
        let ps = t.as_picos();
        match self.short.div(ps) {
            Some(k) => {
                debug_assert_eq!(k, self.tick_at_or_before_general(t));
                k
            }
            None => self.tick_at_or_before_general(t),
        }
    }

    /// [`MclkClock::tick_at_or_before`] without the short division (out of line: the short
    /// one takes every instant of the clocks in use for weeks of simulated time).
    #[cold]
    #[inline(never)]
    fn tick_at_or_before_general(&self, t: Instant) -> u64 {
        let k = match self.ps_per_tick {
            // `p` ≥ 1 (hz ≤ 10¹²).
            Some(p) => return p.div(t.as_picos()),
            // largest k with floor(k·10¹²/f) <= ps  <=>  k·10¹² < (ps+1)·f
            None => {
                let ps = u128::from(t.as_picos());
                ((ps + 1) * u128::from(self.hz) - 1) / PS_PER_S
            }
        };
        u64::try_from(k).unwrap_or(u64::MAX)
    }

    /// The first tick at or after `t`.
    #[inline]
    pub(crate) fn tick_at_or_after(&self, t: Instant) -> u64 {
        let ps = t.as_picos();
        // ⌈n / p⌉ = ⌊(n − 1) / p⌋ + 1 for n ≥ 1; n = 0 wraps to u64::MAX, which no short
        // division takes.
        if let Some(k) = self.short.div(ps.wrapping_sub(1)) {
            debug_assert_eq!(k + 1, self.tick_at_or_after_general(t));
            return k + 1;
        }
        match self.ps_per_tick {
            Some(p) => p.div_ceil(ps),
            None => self.tick_at_or_after_general(t),
        }
    }

    /// [`MclkClock::tick_at_or_after`] without the short division (out of line, as
    /// [`MclkClock::tick_at_or_before_general`]; the reciprocal of an exact clock past the
    /// short range is taken inline).
    #[cold]
    #[inline(never)]
    fn tick_at_or_after_general(&self, t: Instant) -> u64 {
        if let Some(p) = self.ps_per_tick {
            return p.div_ceil(t.as_picos());
        }
        let k = self.tick_at_or_before_general(t);
        if self.instant(k) >= t {
            k
        } else {
            k.saturating_add(1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_exact_and_inexact_clocks() {
        for hz in [20_000_000, 32_000_000, 30_000_000, 7] {
            let c = MclkClock::new(hz);
            for k in [0u64, 1, 2, 3, 999, 1_000_001] {
                let t = c.instant(k);
                assert_eq!(c.tick_at_or_before(t), k, "{hz} {k}");
                assert_eq!(c.tick_at_or_after(t), k, "{hz} {k}");
                let later = Instant::from_picos(t.as_picos() + 1);
                assert_eq!(c.tick_at_or_before(later), k);
                assert_eq!(c.tick_at_or_after(later), k + 1);
            }
        }
    }

    /// Instants at the end of the short division's range and past it (`ShortDivision`) are
    /// divided as below it.
    #[test]
    fn ticks_at_the_end_of_the_short_range_and_past_it() {
        for hz in [20_000_000, 32_000_000] {
            let c = MclkClock::new(hz);
            let p = 1_000_000_000_000 / hz;
            let below = c.short.below();
            assert!(below > 1 << 61, "{hz}");
            for ps in [
                0,
                1,
                p - 1,
                p,
                p + 1,
                below - 1,
                below,
                below + 1,
                below + p,
            ]
            .into_iter()
            .chain([1 << 63, u64::MAX - 1, u64::MAX])
            .chain((0..2 * p).map(|i| below - p + i))
            {
                let t = Instant::from_picos(ps);
                assert_eq!(c.tick_at_or_before(t), ps / p, "{hz} {ps}");
                assert_eq!(c.tick_at_or_after(t), ps.div_ceil(p), "{hz} {ps}");
            }
        }
    }
}
