//! Why a RAM layout cannot be built.

use sercon_regs::Variant;
use sercos_wire::time::BitRate;

/// The layout builder refuses the configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum RamLayoutError {
    /// The structures need more words than the variant's dual-port RAM has.
    #[error("the layout needs {needed} words, the {variant:?} RAM has {available}")]
    DoesNotFit {
        /// The controller.
        variant: Variant,
        /// Words needed, including the 11 fixed words.
        needed: u32,
        /// Words of the RAM (1024 or 2048).
        available: u32,
    },
    /// The bit rate is not available on the controller.
    #[error("{rate} is not available on the {variant:?} (410B: 2 and 4 Mbit/s)")]
    BitRateNotSupported {
        /// The controller.
        variant: Variant,
        /// The bit rate asked for.
        rate: BitRate,
    },
    /// A slave layout for an address the timing plan does not contain.
    #[error("drive {address} is not in the timing plan")]
    UnknownDrive {
        /// The slave's address.
        address: u8,
    },
    /// A data container would hold more words than LEN can say (410B §4.2.2: bits 9-0).
    #[error("a data container of {words} words: LEN holds at most {max}")]
    ContainerTooLong {
        /// Words the container would hold.
        words: u16,
        /// The most LEN can say.
        max: u16,
    },
    /// A service-container buffer outside 1-251 words (8-bit offsets from the container).
    #[error("service-container buffer of {words} words: 1-{max} words fit")]
    ServiceBufferSize {
        /// Words asked for.
        words: u16,
        /// The most that fit.
        max: u16,
    },
}
