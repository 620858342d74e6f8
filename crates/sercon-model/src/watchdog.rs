//! The SERCON816 watchdog (816 §2.6).

/// Watchdog state; times are MCLK ticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Watchdog {
    /// 816 §2.11.2 28H.0 WDOG_STAT: the watchdog is counting.
    pub(crate) running: bool,
    /// When the down counter reaches 0 (meaningful while `running`).
    pub(crate) expiry: u64,
    /// 816 §2.11.2 28H.2 WDOUT_STAT: output WDOGN enabled (set by WDOUT_SET).
    pub(crate) output_enabled: bool,
    /// While WDOGN is active: the tick at which it goes inactive again.
    pub(crate) wdogn_until: Option<u64>,
}

impl Watchdog {
    /// The next tick at which the watchdog changes anything.
    pub(crate) fn next_tick(&self) -> Option<u64> {
        let expiry = self.running.then_some(self.expiry);
        match (expiry, self.wdogn_until) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Loads the down counter with TWDOG at tick `at`.
    // 816 §2.6.3: "T_WDOG = (MCLKDIV + 1) · TWDOG / f_MCLK"; "Each trigger event again
    // loads the counter to the value of TWDOG".
    fn load(&mut self, at: u64, twdog: u16, period: u64) {
        self.expiry = at.saturating_add(u64::from(twdog).saturating_mul(period));
    }

    /// WDOG_START: switches the watchdog on (no effect while it runs).
    // 816 §2.6: "can be activated by writing the control bit WDOG_START. Once activated,
    // not switch off is possible except by software reset."
    pub(crate) fn start(&mut self, at: u64, twdog: u16, period: u64) {
        if !self.running {
            self.running = true;
            self.load(at, twdog, period);
        }
    }

    /// A trigger (42H to WDOG_TRIG, or an MST start with WDOG_MSTEN): reloads a running
    /// watchdog; does nothing to a stopped one.
    // 816 §2.6.4, §2.6.5.
    pub(crate) fn trigger(&mut self, at: u64, twdog: u16, period: u64) {
        if self.running {
            self.load(at, twdog, period);
        }
    }

    /// The counter reached 0 at `at`: the watchdog switches off; WDOGN goes active until
    /// `release` when enabled. Returns whether it expired.
    // 816 §2.6: "If the watchdog activates, it switches off automatically."
    pub(crate) fn expire_at(&mut self, at: u64, release: u64) -> bool {
        if !(self.running && self.expiry == at) {
            return false;
        }
        self.running = false;
        if self.output_enabled {
            // 816 §2.6.1: WDOGN "remains active for the next minimum 2, maximum 3
            // periods of this divider".
            self.wdogn_until = Some(release);
        }
        true
    }

    /// Ends the WDOGN pulse if it ends at `at`.
    pub(crate) fn release_at(&mut self, at: u64) {
        if self.wdogn_until == Some(at) {
            self.wdogn_until = None;
        }
    }

    /// MCLKDIV changed at `at` from `old` to `new` ticks per µs: the counter keeps its
    /// remaining count of µs (816 §2.6.3: it "counts with the given frequency of MCLKDIV").
    pub(crate) fn set_divider(&mut self, at: u64, old: u64, new: u64) {
        if self.running && self.expiry > at && old != 0 {
            let remaining = (self.expiry - at).div_ceil(old);
            self.expiry = at.saturating_add(remaining.saturating_mul(new));
        }
    }

    /// Level of pin WDOGN (active low, 816 §2.2 pin 24).
    pub(crate) fn wdogn_level(&self) -> bool {
        self.wdogn_until.is_none()
    }
}
