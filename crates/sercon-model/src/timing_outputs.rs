//! The timing outputs CON_CLK and DIV_CLK: their state and electrical levels.

use crate::settings::Settings;

/// State behind CON_CLK and DIV_CLK.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct TimingOutputs {
    /// CON_CLK flip-flop: set at TINT0, reset at TINT1 (410B §4.1 0CH.5 "active from
    /// TINT0 to TINT1"); it runs whatever ENCONCLK says, ENCONCLK only gates the pin.
    pub(crate) conclk_set: bool,
    /// Offset (µs in the running cycle) at which the DIV_CLK pulse in progress ends.
    pub(crate) divclk_until: Option<u64>,
    /// DIVCLKMODE = 1: cycles to wait before the next pulse cycle (816 §2.7).
    pub(crate) divclk_countdown: u8,
}

impl TimingOutputs {
    /// Level of pin CON_CLK: inactive unless ENCONCLK; 1-active unless POLCONCLK.
    // 410B §4.1 0CH.5 ENCONCLK, 0CH.6 POLCONCLK.
    pub(crate) fn conclk_level(&self, s: &Settings) -> bool {
        (s.enconclk && self.conclk_set) != s.polconclk
    }

    /// Level of pin DIV_CLK: 1-active unless POLDIVCLK.
    // 410B §4.1 20H.8 POLDIVCLK.
    pub(crate) fn divclk_level(&self, s: &Settings) -> bool {
        self.divclk_until.is_some() != s.poldivclk
    }
}
