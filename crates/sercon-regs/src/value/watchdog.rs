//! The SERCON816 watchdog registers 28H–2AH (816 §2.6, §2.10.2.2, §2.11.2).
//!
//! Register 28H means different things on read and write (ERRATA "816 28H.2", "816
//! 28H.6"), so it has two views: [`WdogStatus`] (read) and [`WdogCommand`] (write).

use crate::value::{flags_register, word_register};

bitflags::bitflags! {
    /// Register 28H as read (816 §2.11.2).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct WdogStatus: u16 {
        /// Watchdog on.
        const WDOG_STAT = 1 << 0;
        /// Interrupt flag: the watchdog has fired.
        const INT_WDOG = 1 << 1;
        /// Output WDOGN enabled.
        #[doc(alias = "WDOOUT_STAT")]
        const WDOUT_STAT = 1 << 2;
        /// INT_WDOG triggers INT0.
        const EN0_INT_WDOG = 1 << 3;
        /// INT_WDOG triggers INT1.
        const EN1_INT_WDOG = 1 << 4;
        /// Master: the watchdog is triggered by the internal MST start.
        const WDOG_MSTEN = 1 << 5;
        /// Interrupt flag: service-container processing after a receive telegram ended.
        const INT_RSCEND = 1 << 6;
        /// INT_RSCEND triggers INT0.
        const EN0_INT_RSCEND = 1 << 7;
        /// INT_RSCEND triggers INT1.
        const EN1_INT_RSCEND = 1 << 8;
    }
}
flags_register!(WdogStatus, WdogCtrl);

bitflags::bitflags! {
    /// Register 28H as written (816 §2.11.2).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct WdogCommand: u16 {
        /// Switch the watchdog on (action; cannot be switched off but by reset, §2.6).
        const WDOG_START = 1 << 0;
        /// Clear INT_WDOG (write 1 to clear).
        const CLR_INT_WDOG = 1 << 1;
        /// Enable output WDOGN (action; ERRATA "816 28H.2").
        #[doc(alias("WDOOUT_SET", "WDOOUT_EN", "WDOEN"))]
        const WDOUT_SET = 1 << 2;
        /// INT_WDOG triggers INT0.
        const EN0_INT_WDOG = 1 << 3;
        /// INT_WDOG triggers INT1.
        const EN1_INT_WDOG = 1 << 4;
        /// Master: trigger the watchdog by the internal MST start.
        const WDOG_MSTEN = 1 << 5;
        /// Clear INT_RSCEND (write 1 to clear).
        const CLR_RSCEND = 1 << 6;
        /// INT_RSCEND triggers INT0.
        const EN0_INT_RSCEND = 1 << 7;
        /// INT_RSCEND triggers INT1.
        const EN1_INT_RSCEND = 1 << 8;
    }
}
flags_register!(WdogCommand, WdogCtrl);

impl WdogCommand {
    /// The R/W enable bits of a status read, as a command that keeps them (and does
    /// not start, set or clear anything): use it for read-modify-write of 28H.
    pub const fn keeping_enables(status: WdogStatus) -> WdogCommand {
        WdogCommand::from_bits_retain(status.bits() & 0x01B8)
    }
}

word_register!(
    /// 29H WDOG_TRIG (W, 816): writing [`WdogTrig::KEY`] (42H) to bits 7-0 triggers
    /// the watchdog (816 §2.6.4).
    #[doc(alias = "WDOG_TRIG")]
    WdogTrig,
    WdogTrig
);

impl WdogTrig {
    /// The trigger value 42H (816 §2.6.4).
    pub const KEY: u8 = 0x42;
    /// The write that triggers the watchdog.
    pub const TRIGGER: WdogTrig = WdogTrig(Self::KEY as u16);

    /// Whether a write of this value triggers the watchdog (bits 7-0 = 42H; bits 15-8
    /// are unused, 816 §2.11.2).
    pub const fn is_trigger(self) -> bool {
        self.0 as u8 == Self::KEY
    }
}

word_register!(
    /// 2AH TWDOG (816): watchdog time constant, in periods of the MCLKDIV time base
    /// (816 §2.6.3).
    #[doc(alias = "TWDOG")]
    Twdog,
    Twdog
);
