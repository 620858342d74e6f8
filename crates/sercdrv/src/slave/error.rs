//! Why the slave driver cannot start or cannot follow the master.

use sercon_regs::Variant;
use sercos_wire::idn::Idn;
use sercos_wire::time::BitRate;

use crate::ram_layout::RamLayoutError;
use crate::timing::TimingError;

/// A slave configuration or cyclic set-up the driver refuses.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SlaveError {
    /// Drive addresses are 1–254 (sercos-telegrams.md, ADR; ERRATA "addresses").
    #[error("drive address {0} is not 1-254")]
    InvalidAddress(u8),
    /// The chip's VERSION register names another controller (410B §4.1 0H; ERRATA "0H VERSION").
    #[error("the chip reports {found:?}, the configuration says {expected:?}")]
    WrongVariant {
        /// The configured variant.
        expected: Variant,
        /// What VERSION says (`None`: an unknown code).
        found: Option<Variant>,
    },
    /// MCLK gives no 1 µs predivider in the variant's MCLKDIV field (410B §4.1 0EH).
    #[error("MCLK of {mclk_hz} Hz gives no MCLKDIV for a 1 us time base")]
    Predivider {
        /// The MCLK frequency.
        mclk_hz: u32,
    },
    /// The bit rate cannot be made from SCLK with the chip's dividers (410B §2 SBAUD,
    /// 1H.6 SWBAUD; 816 §2.3.1).
    #[error("{rate:?} cannot be made from SCLK = {sclk_hz} Hz on the {variant:?}")]
    BitRate {
        /// The controller.
        variant: Variant,
        /// The wanted rate.
        rate: BitRate,
        /// The SCLK frequency.
        sclk_hz: u64,
    },
    /// The phase 0–2 slots cannot be planned for the configured cycle.
    #[error("phase 0-2 timing: {0}")]
    Timing(#[from] TimingError),
    /// The RAM layout does not fit or is refused.
    #[error("RAM layout: {0}")]
    Layout(#[from] RamLayoutError),
    /// A parameter the cyclic set-up needs is missing from the IDN store or unreadable.
    #[error("{0} is missing or unreadable")]
    ParameterMissing(Idn),
    /// A parameter of the cyclic set-up is out of range.
    #[error("{idn} = {value}: {reason}")]
    ParameterInvalid {
        /// The parameter.
        idn: Idn,
        /// Its value.
        value: u32,
        /// What is wrong.
        reason: &'static str,
    },
    /// The device cannot name its cyclic data lengths.
    #[error("cyclic data: {0}")]
    Device(String),
    /// DMA buffering is not served by the slave driver (it needs the host at each telegram).
    #[error("DMA buffering is not supported by the slave driver")]
    DmaNotSupported,
}
