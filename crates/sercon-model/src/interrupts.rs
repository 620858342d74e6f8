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

/// Every interrupt flag of the chip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Flags {
    /// 410B §4.1 4H: INT_RDIST … INT_RERR.
    pub(crate) lo: u16,
    /// 410B §4.1 5H: INT_SC_0 … INT_NEWADR.
    pub(crate) hi: u16,
    /// 816 §2.11.2 28H.1 INT_WDOG.
    pub(crate) wdog: bool,
    /// 816 §2.11.2 28H.6 INT_RSCEND.
    pub(crate) rscend: bool,
}

impl Flags {
    /// Every flag in one word, to see at once what changed: 4H in bits 0–15, 5H in bits
    /// 16–31, INT_WDOG in bit 32, INT_RSCEND in bit 40 (410B §4.1 4H, 5H; 816 §2.11.2 28H).
    #[inline]
    pub(crate) fn word(&self) -> u64 {
        let regs = u32::from(self.lo) | u32::from(self.hi) << 16;
        let ext = u16::from(self.wdog) | u16::from(self.rscend) << 8;
        u64::from(regs) | u64::from(ext) << 32
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
        self.lo & en_lo != 0
            || self.hi & en_hi != 0
            || (self.wdog && s.en_wdog.get(n).copied().unwrap_or(false))
            || (self.rscend && s.en_rscend.get(n).copied().unwrap_or(false))
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
