//! The MCLK predivider that makes the chip's microsecond (MCLKDIV, MCLKST; 410B §4.1 0EH,
//! 816 §2.11.1.2).
//!
//! 410B §4.1 0EH: "MCLKDIV: Predivider value: fMCLK/1 MHz - 1", so one "µs" of every
//! timing register lasts `MCLKDIV + 1` MCLK periods. Reading (spec-notes "predivider"):
//! the predivider counts MCLK periods up from MCLKST; when it has counted past MCLKDIV it
//! wraps to 0 and the µs tick happens. It is loaded with MCLKST when the chip leaves reset
//! and when timing control is triggered (CYCSTART, CYC_CLK), so MCLKST = 0 puts the
//! trigger exactly on the µs grid and MCLKST = s shortens the first µs by `s` periods.

use crate::reciprocal::Reciprocal;

/// The predivider: where its µs ticks fall, in MCLK ticks.
///
/// Invariant: the µs ticks at or after `anchor` are exactly `anchor + k · period`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Predivider {
    /// A µs tick; ticks before it (the first, irregular µs) are not on the grid.
    anchor: u64,
    /// MCLKDIV + 1, in MCLK ticks ([`Reciprocal::divisor`]), as its reciprocal: ticks are
    /// divided into µs several times a cycle, and a 64-bit `div` takes a dozen clocks
    /// (docs/performance.md, session 32).
    period: Reciprocal,
    /// Width of the MCLKDIV / MCLKST fields (5 on the 410B, 6 on the 816).
    bits: u8,
}

impl Predivider {
    /// A predivider loaded with `start` (MCLKST) at tick `at`, dividing by `mclkdiv + 1`.
    pub(crate) fn loaded(at: u64, mclkdiv: u16, start: u16, bits: u8) -> Self {
        let period = u64::from(mclkdiv) + 1;
        Predivider {
            anchor: first_wrap(at, u64::from(start), period, bits),
            period: Reciprocal::new(period),
            bits,
        }
    }

    /// MCLK ticks per µs (MCLKDIV + 1).
    pub(crate) fn period(&self) -> u64 {
        self.period.divisor()
    }

    /// `n / period`.
    #[inline]
    pub(crate) fn periods_in(&self, n: u64) -> u64 {
        self.period.div(n)
    }

    /// `n.div_ceil(period)`.
    #[inline]
    pub(crate) fn periods_begun_in(&self, n: u64) -> u64 {
        self.period.div_ceil(n)
    }

    /// The first µs tick strictly after MCLK tick `k`.
    #[inline(always)]
    pub(crate) fn tick_after(&self, k: u64) -> u64 {
        if k < self.anchor {
            self.anchor
        } else {
            let n = self.period.div(k - self.anchor) + 1;
            self.anchor
                .saturating_add(n.saturating_mul(self.period.divisor()))
        }
    }

    /// Reloads the predivider with MCLKST at tick `at` (timing-control trigger).
    // 410B §4.1 0EH: "MCLKST: Initial value for predivider".
    pub(crate) fn reload(&mut self, at: u64, start: u16) {
        self.anchor = first_wrap(at, u64::from(start), self.period.divisor(), self.bits);
    }

    /// A new MCLKDIV written at tick `at`: the counter keeps its count and now wraps after
    /// `mclkdiv` (spec-notes "MCLKDIV written while counting").
    pub(crate) fn set_divider(&mut self, at: u64, mclkdiv: u16) {
        let new_period = u64::from(mclkdiv) + 1;
        let period = self.period.divisor();
        if new_period == period {
            return;
        }
        let count = if at >= self.anchor {
            self.period.div_rem(at - self.anchor).1
        } else {
            // Still in the first, irregular µs: the count is what is left to run.
            period.saturating_sub(self.anchor - at)
        };
        self.period = Reciprocal::new(new_period);
        self.anchor = first_wrap(at, count, new_period, self.bits);
    }
}

/// The tick at which a counter holding `count` at tick `at` wraps, dividing by `period`.
/// A count above the divider runs on to the end of the field and wraps through 0.
fn first_wrap(at: u64, count: u64, period: u64, bits: u8) -> u64 {
    let field = 1u64 << bits;
    let to_wrap = if count < period {
        period - count
    } else {
        field.saturating_sub(count) + period
    };
    at.saturating_add(to_wrap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mclkst_zero_puts_the_load_on_the_grid() {
        let p = Predivider::loaded(100, 19, 0, 5);
        assert_eq!(p.tick_after(100), 120);
        assert_eq!(p.tick_after(119), 120);
        assert_eq!(p.tick_after(120), 140);
    }

    #[test]
    fn mclkst_shortens_the_first_microsecond() {
        let p = Predivider::loaded(100, 19, 5, 5);
        assert_eq!(p.tick_after(100), 115);
        assert_eq!(p.tick_after(115), 135);
        // above MCLKDIV: counts to 31, wraps, then a whole period
        let q = Predivider::loaded(0, 9, 30, 5);
        assert_eq!(q.tick_after(0), 2 + 10);
    }

    #[test]
    fn new_divider_keeps_the_count() {
        let mut p = Predivider::loaded(0, 19, 0, 5);
        p.set_divider(25, 9); // count 5 of 10
        assert_eq!(p.tick_after(25), 30);
        assert_eq!(p.tick_after(30), 40);
    }

    proptest::proptest! {
        /// The reciprocal's quotients are the division's (410B §4.1 0EH: one µs is
        /// MCLKDIV + 1 MCLK periods): the µs tick after any tick, the µs counted and begun
        /// in any span, and the count a new divider keeps, for every MCLKDIV of the 816's
        /// 6-bit field.
        #[test]
        fn the_reciprocal_divides_as_the_division(
            mclkdiv in 0u16..64,
            start in 0u16..64,
            at in 0u64..1 << 50,
            k in proptest::prelude::any::<u64>(),
            new_div in 0u16..64,
        ) {
            let p = Predivider::loaded(at, mclkdiv, start, 6);
            let period = u64::from(mclkdiv) + 1;
            let expected = if k < p.anchor {
                p.anchor
            } else {
                p.anchor.saturating_add(((k - p.anchor) / period + 1).saturating_mul(period))
            };
            proptest::prop_assert_eq!(p.tick_after(k), expected);
            proptest::prop_assert_eq!(p.periods_in(k), k / period);
            proptest::prop_assert_eq!(p.periods_begun_in(k), k.div_ceil(period));
            let mut q = p;
            let when = at.saturating_add(k % (1 << 20));
            q.set_divider(when, new_div);
            let new_period = u64::from(new_div) + 1;
            let expected_anchor = if when >= p.anchor {
                first_wrap(when, (when - p.anchor) % period, new_period, 6)
            } else {
                first_wrap(when, period.saturating_sub(p.anchor - when), new_period, 6)
            };
            if new_div != mclkdiv {
                proptest::prop_assert_eq!(q.anchor, expected_anchor);
            }
        }
    }
}
