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

    /// [`MclkClock::tick_at_or_after`] of `t` and [`MclkClock::instant`] of that tick: in the
    /// short division's range the instant is a product that cannot saturate
    /// ([`ShortDivision::div_and_next_multiple`]).
    #[inline]
    pub(crate) fn tick_and_instant_at_or_after(&self, t: Instant) -> (u64, Instant) {
        // As `tick_at_or_after`: ⌈n / p⌉ = ⌊(n − 1) / p⌋ + 1 for n ≥ 1, and n = 0 wraps to
        // u64::MAX, which no short division takes.
        if let Some((q, at)) = self
            .short
            .div_and_next_multiple(t.as_picos().wrapping_sub(1))
        {
            let at = Instant::from_picos(at);
            debug_assert_eq!((q + 1, at), {
                let k = self.tick_at_or_after(t);
                (k, self.instant(k))
            });
            return (q + 1, at);
        }
        let k = self.tick_at_or_after(t);
        (k, self.instant(k))
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

/// An MCLK tick that may be none, as one plain `u64` with `u64::MAX` for none: the earliest
/// of several is one `min` and "due by `limit`" one comparison, where `Option<u64>` takes a
/// tag and branches for each (the event loop's next ticks, `Chip::advance_to`).
///
/// Tick `u64::MAX` reads as none, in every build: the ticks are MCLK ticks of instants
/// (`tick_at_or_after`, below `u64::MAX` at every MCLK below 1 THz) or sums that saturate,
/// and a sum that saturated means "never" (its true tick lies past `Instant::MAX`, the end
/// of representable time, which no advance passes). Only at the top MCLK the configuration
/// accepts (1 THz, a tick per picosecond) can a computed tick be `u64::MAX`: an event at
/// the very last picosecond, or (the case a bus write reaches: a watchdog started within
/// its interval of the end) a saturated sum; both are taken as never, as the saturated sum
/// truly is (`watchdog_816::a_watchdog_expiring_past_the_end_of_time_never_fires`). The
/// general computations (`Option`s) are compared with it in debug builds through
/// [`Due::from_option`], which maps `Some(u64::MAX)` to none the same way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Due(u64);

impl Default for Due {
    /// No tick.
    fn default() -> Self {
        Due::NONE
    }
}

impl Due {
    /// No tick.
    pub(crate) const NONE: Due = Due(u64::MAX);

    /// Tick `tick` (`u64::MAX`: none, see [`Due`]).
    #[inline]
    pub(crate) fn at(tick: u64) -> Due {
        Due(tick)
    }

    /// The tick of `tick`, [`Due::NONE`] for `None` (and for `Some(u64::MAX)`, see [`Due`]).
    #[inline]
    pub(crate) fn from_option(tick: Option<u64>) -> Due {
        Due(tick.unwrap_or(u64::MAX))
    }

    /// The tick `raw`, none for `u64::MAX` (a minimum over ticks that starts from
    /// `u64::MAX`).
    #[inline]
    pub(crate) fn from_raw(raw: u64) -> Due {
        Due(raw)
    }

    /// The tick, `None` for none.
    #[inline]
    pub(crate) fn get(self) -> Option<u64> {
        (self.0 != u64::MAX).then_some(self.0)
    }

    /// The tick, `u64::MAX` for none.
    #[inline]
    pub(crate) fn raw(self) -> u64 {
        self.0
    }

    /// Whether this is tick `tick` (a tick, below `u64::MAX`): one comparison, where
    /// `Option<u64> == Some(tick)` tests the tag too.
    #[inline]
    pub(crate) fn is(self, tick: u64) -> bool {
        debug_assert_ne!(tick, u64::MAX, "u64::MAX is no tick to ask for (Due)");
        self.0 == tick
    }

    /// Whether there is a tick at or before `tick` (any `u64`): one comparison, before the
    /// tick after `tick`, which at `u64::MAX` saturates so that none (`u64::MAX`) is not due
    /// (and every tick, below it, is). Where `tick` is one less than a tick (the step's quiet
    /// events before its own), the addition folds away.
    #[inline]
    pub(crate) fn due_by(self, tick: u64) -> bool {
        self.0 < tick.saturating_add(1)
    }

    /// Whether there is a tick.
    #[inline]
    pub(crate) fn is_some(self) -> bool {
        self.0 != u64::MAX
    }

    /// The tick if it is at or before `limit`, none otherwise (none stays none: its
    /// `u64::MAX` is above every `limit` but `u64::MAX`, where it is none itself).
    #[inline]
    pub(crate) fn by(self, limit: u64) -> Due {
        if self.0 <= limit { self } else { Due::NONE }
    }

    /// Whether there is no tick at or before `tick`, for `tick` a tick (below `u64::MAX`):
    /// none is after every one. (At `u64::MAX` none is not after it: one comparison.)
    #[inline]
    pub(crate) fn after(self, tick: u64) -> bool {
        self.0 > tick
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `Due` kept in state (the telegram processor's transmit end, the MST deadline) answers
    /// as the `Option<u64>` it replaces: `is` as `== Some(tick)`, `due_by` as "`Some` and at or
    /// before", none never, at every tick up to `u64::MAX`.
    #[test]
    fn a_due_answers_as_its_option() {
        let ticks = [0u64, 1, 5, 6, 7, u64::MAX - 2, u64::MAX - 1];
        let dues = ticks.map(|t| (Due::at(t), Some(t)));
        for (due, option) in dues.into_iter().chain([(Due::NONE, None)]) {
            assert_eq!(Due::from_option(option), due);
            assert_eq!(due.get(), option);
            assert_eq!(due.is_some(), option.is_some());
            for tick in ticks.into_iter().chain([u64::MAX]) {
                if tick != u64::MAX {
                    assert_eq!(due.is(tick), option == Some(tick), "{due:?} {tick}");
                }
                assert_eq!(
                    due.due_by(tick),
                    option.is_some_and(|t| t <= tick),
                    "{due:?} {tick}"
                );
            }
        }
        assert_eq!(Due::default(), Due::NONE);
    }

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
                assert_eq!(c.tick_and_instant_at_or_after(t), (k, t), "{hz} {k}");
                assert_eq!(
                    c.tick_and_instant_at_or_after(later),
                    (k + 1, c.instant(k + 1)),
                    "{hz} {k}"
                );
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
                let k = ps.div_ceil(p);
                assert_eq!(
                    c.tick_and_instant_at_or_after(t),
                    (k, Instant::from_picos(k.saturating_mul(p))),
                    "{hz} {ps}"
                );
            }
        }
    }

    /// `Due` answers as the `Option<u64>` it stands for: minima, "due by `limit`" and
    /// "after `tick`", with none above every tick.
    #[test]
    fn due_is_the_option_it_stands_for() {
        let ticks = [None, Some(0), Some(1), Some(7), Some(u64::MAX - 1)];
        for a in ticks {
            let da = Due::from_option(a);
            assert_eq!(da.get(), a);
            assert_eq!(da.raw(), a.unwrap_or(u64::MAX));
            for b in ticks {
                let db = Due::from_option(b);
                let min = match (a, b) {
                    (Some(x), Some(y)) => Some(x.min(y)),
                    (x, y) => x.or(y),
                };
                assert_eq!(da.min(db).get(), min, "{a:?} {b:?}");
            }
            for limit in [0, 1, 6, 7, 8, u64::MAX - 1, u64::MAX] {
                assert_eq!(
                    da.by(limit).get(),
                    a.filter(|k| *k <= limit),
                    "{a:?} {limit}"
                );
                if limit != u64::MAX {
                    assert_eq!(
                        da.after(limit),
                        a.is_none_or(|k| k > limit),
                        "{a:?} {limit}"
                    );
                }
            }
        }
        assert_eq!(Due::at(3), Due::from_option(Some(3)));
        assert_eq!(Due::from_raw(u64::MAX), Due::NONE);
    }
}
