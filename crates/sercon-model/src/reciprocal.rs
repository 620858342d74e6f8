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

    proptest! {
        #[test]
        fn equals_plain_division(n in any::<u64>(), d in 1..=u64::MAX, small in 1u64..100_000) {
            for d in [d, small] {
                let r = Reciprocal::new(d);
                prop_assert_eq!(r.div_rem(n), (n / d, n % d));
                prop_assert_eq!(r.div(n), n / d);
                prop_assert_eq!(r.div_ceil(n), n.div_ceil(d));
            }
        }
    }
}
