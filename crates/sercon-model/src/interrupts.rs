//! Interrupt flags and the interrupt outputs INT0 and INT1 (410B §4.1 3H–9H, 816 §2.11.2
//! 28H).

use crate::settings::Settings;

/// 410B §4.1 4H.2 INT_COMBLK0.
pub(crate) const INT_COMBLK0: u16 = 1 << 2;
/// 410B §4.1 4H.3 INT_COMBLK1.
pub(crate) const INT_COMBLK1: u16 = 1 << 3;
/// 410B §4.1 4H.4 INT_COMEND.
pub(crate) const INT_COMEND: u16 = 1 << 4;
/// 410B §4.1 5H.13 INT_DIVCLK.
pub(crate) const INT_DIVCLK: u16 = 1 << 13;

/// Every interrupt flag of the chip, held as one word: 4H in bits 0–15, 5H in bits 16–31,
/// INT_WDOG in bit 32, INT_RSCEND in bit 40 (410B §4.1 4H, 5H; 816 §2.11.2 28H). The event
/// loop compares the whole word before and after its steps ([`Flags::word`], a load: it was
/// put together from four fields at every compare, ≈ 370 instructions a ring-8 cycle); a
/// flag raised is one `or` into it as into a field.
#[derive(Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Flags {
    /// The flags, laid out as [`Flags::word`] gives them.
    w: u64,
}

/// INT_WDOG's bit in [`Flags::word`].
const WORD_WDOG: u64 = 1 << 32;
/// INT_RSCEND's bit in [`Flags::word`].
const WORD_RSCEND: u64 = 1 << 40;

/// As the four fields the flags were (`lo`, `hi`, `wdog`, `rscend`): a chip's `Debug` text
/// stays what it was.
impl std::fmt::Debug for Flags {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Flags")
            .field("lo", &self.lo())
            .field("hi", &self.hi())
            .field("wdog", &self.wdog())
            .field("rscend", &self.rscend())
            .finish()
    }
}

impl Flags {
    /// Every flag in one word, to see at once what changed: 4H in bits 0–15, 5H in bits
    /// 16–31, INT_WDOG in bit 32, INT_RSCEND in bit 40 (410B §4.1 4H, 5H; 816 §2.11.2 28H).
    #[inline]
    pub(crate) fn word(&self) -> u64 {
        self.w
    }

    /// 410B §4.1 4H: INT_RDIST … INT_RERR.
    #[inline]
    pub(crate) fn lo(&self) -> u16 {
        self.w as u16
    }

    /// 410B §4.1 5H: INT_SC_0 … INT_NEWADR.
    #[inline]
    pub(crate) fn hi(&self) -> u16 {
        (self.w >> 16) as u16
    }

    /// 816 §2.11.2 28H.1 INT_WDOG.
    #[inline]
    pub(crate) fn wdog(&self) -> bool {
        self.w & WORD_WDOG != 0
    }

    /// 816 §2.11.2 28H.6 INT_RSCEND.
    #[inline]
    pub(crate) fn rscend(&self) -> bool {
        self.w & WORD_RSCEND != 0
    }

    /// Sets the flags `bits` of 4H.
    #[inline]
    pub(crate) fn raise_lo(&mut self, bits: u16) {
        self.w |= u64::from(bits);
    }

    /// Sets the flags `bits` of 5H.
    #[inline]
    pub(crate) fn raise_hi(&mut self, bits: u16) {
        self.w |= u64::from(bits) << 16;
    }

    /// Clears the flags `bits` of 4H.
    #[inline]
    pub(crate) fn clear_lo(&mut self, bits: u16) {
        self.w &= !u64::from(bits);
    }

    /// Clears the flags `bits` of 5H.
    #[inline]
    pub(crate) fn clear_hi(&mut self, bits: u16) {
        self.w &= !(u64::from(bits) << 16);
    }

    /// Sets INT_WDOG to `value`.
    #[inline]
    pub(crate) fn set_wdog(&mut self, value: bool) {
        self.w = (self.w & !WORD_WDOG) | if value { WORD_WDOG } else { 0 };
    }

    /// Sets INT_RSCEND to `value`.
    #[inline]
    pub(crate) fn set_rscend(&mut self, value: bool) {
        self.w = (self.w & !WORD_RSCEND) | if value { WORD_RSCEND } else { 0 };
    }

    /// Whether an enabled flag requests interrupt output `n` (0 or 1): INTFL0 / INTFL1.
    ///
    /// Reading (spec-notes "INTFL"): INTFLn shows the request whether or not ENINTn lets
    /// it out on the pin, so software can poll with the pin disabled.
    // 410B §4.1 6H–9H: "Interrupt flag activates INTn"; 816 §2.11.2 28H.3/4, 28H.7/8.
    pub(crate) fn request(&self, s: &Settings, n: usize) -> bool {
        let (en_lo, en_hi) = match (s.en_lo.get(n), s.en_hi.get(n)) {
            (Some(lo), Some(hi)) => (*lo, *hi),
            _ => return false,
        };
        self.lo() & en_lo != 0
            || self.hi() & en_hi != 0
            || (self.wdog() && s.en_wdog.get(n).copied().unwrap_or(false))
            || (self.rscend() && s.en_rscend.get(n).copied().unwrap_or(false))
    }

    /// The electrical level of pin INTn: active when requested and ENINTn = 1; active
    /// high when POLINTn = 0, active low when POLINTn = 1.
    // 410B §4.1 3H.1-5 (ERRATA "410B 3H.1 ENINT0", "410B 3H.2/3H.5 POLINT0/1").
    pub(crate) fn pin_level(&self, s: &Settings, n: usize) -> bool {
        let enabled = s.enint.get(n).copied().unwrap_or(false);
        let active_low = s.polint.get(n).copied().unwrap_or(false);
        (enabled && self.request(s, n)) != active_low
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The flags as the four fields they were held in before they were one word.
    #[derive(Debug, Default)]
    #[allow(dead_code)] // Read through `Debug` only.
    struct Fields {
        lo: u16,
        hi: u16,
        wdog: bool,
        rscend: bool,
    }

    proptest! {
        /// Raising, clearing and setting flags in the one word reads back as the four fields
        /// do, with the word laid out as `Flags::word` documents (4H, 5H, INT_WDOG at bit 32,
        /// INT_RSCEND at bit 40) and the same `Debug` text.
        #[test]
        fn the_flag_word_is_the_four_fields(ops in prop::collection::vec((0u8..6, any::<u16>(), any::<bool>()), 0..40)) {
            let mut f = Flags::default();
            let mut m = Fields::default();
            for (op, bits, value) in ops {
                match op {
                    0 => {
                        f.raise_lo(bits);
                        m.lo |= bits;
                    }
                    1 => {
                        f.raise_hi(bits);
                        m.hi |= bits;
                    }
                    2 => {
                        f.clear_lo(bits);
                        m.lo &= !bits;
                    }
                    3 => {
                        f.clear_hi(bits);
                        m.hi &= !bits;
                    }
                    4 => {
                        f.set_wdog(value);
                        m.wdog = value;
                    }
                    _ => {
                        f.set_rscend(value);
                        m.rscend = value;
                    }
                }
                prop_assert_eq!((f.lo(), f.hi(), f.wdog(), f.rscend()), (m.lo, m.hi, m.wdog, m.rscend));
                let word = u64::from(m.lo)
                    | u64::from(m.hi) << 16
                    | u64::from(m.wdog) << 32
                    | u64::from(m.rscend) << 40;
                prop_assert_eq!(f.word(), word);
                prop_assert_eq!(format!("{f:?}").replace("Flags", "Fields"), format!("{m:?}"));
            }
        }
    }
}
