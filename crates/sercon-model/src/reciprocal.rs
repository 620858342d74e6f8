//! Division by a divisor fixed in advance (an MCLK period, a bit time), by a multiplication
//! with its precomputed reciprocal and one correction step instead of a 64-bit `div`
//! (≈ 3.5 % of the controller pair's time went to divisions of instants into ticks and bit
//! positions; `docs/performance.md`, "Controller pair"). Exact for every dividend.

/// A divisor `d` ≥ 1 with `m = ⌊(2⁶⁴ − 1) / d⌋`.
///
/// For any `n` < 2⁶⁴, `q = ⌊n · m / 2⁶⁴⌋` is ⌊n / d⌋ or one less: `m · d ≥ 2⁶⁴ − d` gives
/// `n · m / 2⁶⁴ ≥ n / d − n / 2⁶⁴ > n / d − 1`, and `m · d < 2⁶⁴` gives
/// `n · m / 2⁶⁴ < n / d`. So the remainder
/// `n − q · d` is below `2d`, and one comparison corrects `q`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Reciprocal {
    d: u64,
    m: u64,
}

impl Reciprocal {
    /// The reciprocal of `d` (0 is taken as 1).
    pub(crate) fn new(d: u64) -> Self {
        let d = d.max(1);
        Reciprocal { d, m: u64::MAX / d }
    }

    /// The divisor.
    pub(crate) fn divisor(self) -> u64 {
        self.d
    }

    /// `(n / d, n % d)`.
    #[inline]
    pub(crate) fn div_rem(self, n: u64) -> (u64, u64) {
        // The high half of a 128-bit product is below 2⁶⁴: the cast keeps it whole.
        let q = ((u128::from(n) * u128::from(self.m)) >> 64) as u64;
        // q ≤ n / d, so q · d ≤ n: neither the product nor the difference wraps.
        let r = n - q * self.d;
        if r >= self.d {
            (q + 1, r - self.d)
        } else {
            (q, r)
        }
    }

    /// `n / d`.
    #[inline]
    pub(crate) fn div(self, n: u64) -> u64 {
        self.div_rem(n).0
    }

    /// `n.div_ceil(d)`.
    #[inline]
    pub(crate) fn div_ceil(self, n: u64) -> u64 {
        let (q, r) = self.div_rem(n);
        q + u64::from(r != 0)
    }
}

/// Division by a divisor `d` > 2¹² fixed in advance for dividends below a bound: the
/// quotient is the high half of one product shifted by a constant, with no correction step
/// (`MclkClock`'s instants into ticks: the bound is 47 days for 32 MHz, 28 days for
/// 20 MHz; later instants take [`Reciprocal`]).
///
/// With `S` = [`ShortDivision::SHIFT`], `m = ⌈2⁶⁴⁺ˢ / d⌉ = (2⁶⁴⁺ˢ + e) / d` for some
/// 0 ≤ `e` < `d`, and `m` < 2⁶⁴ as `d` > 2ˢ. For `n = q · d + r` (`r` < `d`),
/// `n · m / 2⁶⁴⁺ˢ = q + (r + n · e / 2⁶⁴⁺ˢ) / d`, whose floor is `q` when `n · e` < 2⁶⁴⁺ˢ
/// (then `r` plus less than 1 stays below `d`): every `n` below `⌈2⁶⁴⁺ˢ / e⌉`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ShortDivision {
    m: u64,
    /// Dividends below this are divided so (0: none). At most `2⁶⁴ − d`: the multiple of
    /// `d` after a quotient of the range, `(n / d + 1) · d` ≤ `n + d`, is below `2⁶⁴`
    /// ([`ShortDivision::div_and_next_multiple`]).
    below: u64,
    /// The divisor `d`.
    d: u64,
}

impl ShortDivision {
    /// The constant shift `S`.
    const SHIFT: u32 = 12;

    /// No dividend is divided so.
    pub(crate) const NONE: ShortDivision = ShortDivision {
        m: 0,
        below: 0,
        d: 0,
    };

    /// The short division by `d` (for `d` ≤ 2¹², [`ShortDivision::NONE`]).
    pub(crate) fn new(d: u64) -> Self {
        if d <= 1 << Self::SHIFT {
            return Self::NONE;
        }
        let x = 1u128 << (64 + Self::SHIFT);
        let d = u128::from(d);
        let m = x.div_ceil(d);
        let e = m * d - x;
        let below = if e == 0 { u128::MAX } else { x.div_ceil(e) };
        // Capped at 2⁶⁴ − d (`below`'s rustdoc): d > 2¹² here, so 2⁶⁴ − d fits.
        let cap = (1u128 << 64) - d;
        match (
            u64::try_from(m),
            u64::try_from(below.min(cap)),
            u64::try_from(d),
        ) {
            (Ok(m), Ok(below), Ok(d)) => ShortDivision { m, below, d },
            _ => Self::NONE,
        }
    }

    /// The bound: dividends below it are divided so.
    #[cfg(test)]
    pub(crate) fn below(self) -> u64 {
        self.below
    }

    /// `n / d` when `n` is below the bound.
    #[inline]
    pub(crate) fn div(self, n: u64) -> Option<u64> {
        if n < self.below {
            // The high half of a 128-bit product is below 2⁶⁴: the cast keeps it whole.
            Some((((u128::from(n) * u128::from(self.m)) >> 64) as u64) >> Self::SHIFT)
        } else {
            None
        }
    }

    /// `n / d` and the next multiple of `d` after `n`, `(n / d + 1) · d`, when `n` is below
    /// the bound.
    #[inline]
    pub(crate) fn div_and_next_multiple(self, n: u64) -> Option<(u64, u64)> {
        let q = self.div(n)?;
        // (q + 1) · d ≤ n + d < below + d ≤ 2⁶⁴ (`below`'s cap): neither wraps.
        let next = q.wrapping_add(1).wrapping_mul(self.d);
        debug_assert_eq!(
            Some(next),
            q.checked_add(1).and_then(|k| k.checked_mul(self.d)),
            "a short division's next multiple"
        );
        Some((q, next))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn edges_of_the_range() {
        for d in [
            1,
            2,
            3,
            7,
            31_250,
            62_500,
            1 << 32,
            u64::MAX / 3,
            u64::MAX - 1,
            u64::MAX,
        ] {
            let r = Reciprocal::new(d);
            for n in [0, 1, d - 1, d, d.saturating_add(1), u64::MAX - 1, u64::MAX] {
                assert_eq!(r.div_rem(n), (n / d, n % d), "{n} / {d}");
                assert_eq!(r.div_ceil(n), n.div_ceil(d), "{n} / {d}");
            }
        }
        assert_eq!(Reciprocal::new(0).div(5), 5, "0 is taken as 1");
    }

    /// The bound is where the short division stops being exact: the first dividend at or
    /// above it whose remainder is `d − 1` has the quotient one too high there.
    #[test]
    fn the_short_division_holds_below_its_bound_only() {
        for d in [
            4_097,
            25_000,
            31_250,
            50_000,
            62_500,
            1_000_000_007,
            142_857_142_857,
        ] {
            let s = ShortDivision::new(d);
            assert!(s.below > 0, "{d}");
            for n in [
                0,
                1,
                d - 1,
                d,
                d + 1,
                s.below - 1,
                s.below.saturating_sub(d),
            ] {
                assert_eq!(s.div(n), Some(n / d), "{n} / {d}");
            }
            assert_eq!(s.div(s.below), None);
            if s.below < u64::MAX - d {
                let n = s.below + (d - 1 - s.below % d);
                let q = ((u128::from(n) * u128::from(s.m)) >> 64) as u64 >> ShortDivision::SHIFT;
                assert_eq!(q, n / d + 1, "{d}: the product past the bound");
                assert_eq!(s.div(n), None);
            }
        }
        assert_eq!(ShortDivision::new(1 << 12), ShortDivision::NONE);
        assert_eq!(ShortDivision::new(0), ShortDivision::NONE);
        assert_eq!(ShortDivision::NONE.div(0), None);
    }

    /// The next multiple after a quotient of the short range stays below 2⁶⁴ at the top of
    /// the range: the bound is capped at 2⁶⁴ − d (divisors of e = 0, powers of two, had no
    /// bound below u64::MAX before the cap).
    #[test]
    fn the_next_multiple_fits_up_to_the_bound() {
        for d in [
            4_097,
            1 << 13,
            31_250,
            62_500,
            1 << 40,
            142_857_142_857,
            u64::MAX / 3,
            u64::MAX - 1,
        ] {
            let s = ShortDivision::new(d);
            if s == ShortDivision::NONE {
                continue;
            }
            assert!(u128::from(s.below) + u128::from(d) <= 1 << 64, "{d}");
            for n in [0, 1, d - 1, d, s.below - 1, s.below.saturating_sub(d)] {
                let q = n / d;
                let next = (u128::from(q) + 1) * u128::from(d);
                assert_eq!(
                    s.div_and_next_multiple(n).map(|(q, m)| (q, u128::from(m))),
                    (n < s.below).then_some((q, next)),
                    "{n} / {d}"
                );
            }
            assert_eq!(s.div_and_next_multiple(s.below), None, "{d}");
        }
    }

    proptest! {
        #[test]
        fn the_next_multiple_equals_plain_arithmetic(d in 4_097..=u64::MAX, f in any::<u64>()) {
            let s = ShortDivision::new(d);
            let n = f % s.below.max(1);
            let want = (n < s.below).then(|| {
                let q = n / d;
                (q, u64::try_from((u128::from(q) + 1) * u128::from(d)).ok())
            });
            prop_assert_eq!(s.div_and_next_multiple(n).map(|(q, m)| (q, Some(m))), want);
        }

        #[test]
        fn equals_plain_division(n in any::<u64>(), d in 1..=u64::MAX, small in 1u64..100_000) {
            for d in [d, small] {
                let r = Reciprocal::new(d);
                prop_assert_eq!(r.div_rem(n), (n / d, n % d));
                prop_assert_eq!(r.div(n), n / d);
                prop_assert_eq!(r.div_ceil(n), n.div_ceil(d));
                if let Some(q) = ShortDivision::new(d).div(n) {
                    prop_assert_eq!(q, n / d);
                }
            }
        }

        #[test]
        fn the_short_division_equals_plain_division(d in 4_097..=u64::MAX, f in any::<u64>()) {
            let s = ShortDivision::new(d);
            let n = f % s.below.max(1);
            prop_assert_eq!(s.div(n), (n < s.below).then(|| n / d));
        }
    }
}
