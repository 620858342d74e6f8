//! The chip's configuration: variant, clock frequencies and strap pins.

use sercon_regs::Variant;

/// Levels of the input pins that are sampled as straps (410B §2, 816 §2.2, §2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Straps {
    /// Pin SBAUD (pin 29): bit-rate selection (816 §2.3.1 table).
    pub sbaud: bool,
    /// Pin 28: SBAUD16 on the SERCON816, SREGEN on the SERCON410B (816 §2.2).
    #[doc(alias = "SREGEN")]
    pub sbaud16: bool,
    /// Pin TM0: test mode, and REPON after reset on the 816 (816 §2.3.3).
    pub tm0: bool,
    /// Pin TM1: test mode, and REPON after reset on the 816 (816 §2.3.3).
    pub tm1: bool,
}

impl Straps {
    /// The straps of a board in normal operation: TM0 = TM1 = 1 (no test signal), SBAUD =
    /// pin 28 = 0. The datasheet's inputs have pull-ups (410B §3.3 I_IL) and TM0 = TM1 = 0
    /// would be the test signal continuous light (410B §2 TM0, TM1); on the 816 they also make
    /// REPON reset to 1 (816 §2.3.3).
    pub const NORMAL: Straps = Straps {
        sbaud: false,
        sbaud16: false,
        tm0: true,
        tm1: true,
    };
}

/// Everything fixed about one chip: which controller it is, its clocks and straps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ChipConfig {
    /// Which controller (410B or 816).
    pub variant: Variant,
    /// Frequency of the MCLK input in Hz (410B §3.4.1; 816 §2.4.1).
    pub mclk_hz: u64,
    /// Frequency of the SCLK input in Hz (410B §3.4.2; 816 §2.3.1).
    pub sclk_hz: u64,
    /// Strap pin levels.
    pub straps: Straps,
}

/// A configuration the model cannot run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ConfigError {
    /// MCLK must run: the whole time base derives from it.
    #[error("MCLK frequency must not be 0 Hz")]
    ZeroMclk,
    /// MCLK faster than 1 THz cannot be expressed in picoseconds.
    #[error("MCLK frequency {0} Hz is above 1 THz")]
    MclkTooFast(u64),
}

impl ChipConfig {
    /// A SERCON816 with a 32 MHz MCLK and a 64 MHz SCLK (816 §2.3.1, §2.4.1), straps
    /// [`Straps::NORMAL`] (SBAUD16 = 0: the 816's own bit rates; TM0 = TM1 = 1).
    #[doc(alias = "SERCON816")]
    pub fn sercon816() -> Self {
        ChipConfig {
            variant: Variant::Sercon816,
            mclk_hz: 32_000_000,
            sclk_hz: 64_000_000,
            straps: Straps::NORMAL,
        }
    }

    /// A SERCON410B with a 20 MHz MCLK and a 64 MHz SCLK (410B §3.2, §3.4.1), SREGEN = 1
    /// (internal clock regeneration), TM0 = TM1 = 1 ([`Straps::NORMAL`]).
    #[doc(alias = "SERCON410B")]
    pub fn sercon410b() -> Self {
        ChipConfig {
            variant: Variant::Sercon410b,
            mclk_hz: 20_000_000,
            sclk_hz: 64_000_000,
            straps: Straps {
                sbaud16: true,
                ..Straps::NORMAL
            },
        }
    }

    /// Checks that the model can run this configuration.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.mclk_hz == 0 {
            return Err(ConfigError::ZeroMclk);
        }
        if self.mclk_hz > 1_000_000_000_000 {
            return Err(ConfigError::MclkTooFast(self.mclk_hz));
        }
        Ok(())
    }
}
