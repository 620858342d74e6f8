//! Typed values of the control registers: one type per register (two for 28H, whose bits
//! mean different things on read and on write), each convertible from and to the raw
//! word without loss, so that reserved and status bits survive a read-modify-write.

pub mod control;
pub mod interrupt;
pub mod pointer;
pub mod timing;
pub mod watchdog;

use crate::register::Register;

/// A typed view of one control register's 16-bit word.
///
/// `from_bits(x).bits() == x` for every `x`: no bit is lost.
pub trait RegisterValue: Copy {
    /// The register this value is read from and written to.
    const REGISTER: Register;
    /// The typed view of a raw word.
    fn from_bits(bits: u16) -> Self;
    /// The raw word.
    fn bits(self) -> u16;
}

/// Implements [`RegisterValue`] for a bitflags type (keeping unknown bits).
macro_rules! flags_register {
    ($ty:ty, $reg:ident) => {
        impl $crate::value::RegisterValue for $ty {
            const REGISTER: $crate::register::Register = $crate::register::Register::$reg;
            fn from_bits(bits: u16) -> Self {
                <$ty>::from_bits_retain(bits)
            }
            fn bits(self) -> u16 {
                <$ty>::bits(&self)
            }
        }
    };
}
pub(crate) use flags_register;

/// Declares a `pub struct $name(pub u16)` register value and implements
/// [`RegisterValue`] for it.
macro_rules! word_register {
    ($(#[$meta:meta])* $name:ident, $reg:ident) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        pub struct $name(pub u16);

        impl $crate::value::RegisterValue for $name {
            const REGISTER: $crate::register::Register = $crate::register::Register::$reg;
            fn from_bits(bits: u16) -> Self {
                $name(bits)
            }
            fn bits(self) -> u16 {
                self.0
            }
        }
    };
}
pub(crate) use word_register;

word_register!(
    /// 00H VERSION: the circuit code (410B §4.1; 816 §2.11.1.1).
    #[doc(alias = "VERSION")]
    Version,
    Version
);

impl Version {
    /// The variant this circuit code identifies, if any.
    pub const fn variant(self) -> Option<crate::Variant> {
        crate::Variant::from_version(self.0)
    }
}

word_register!(
    /// 27H: a word popped from RFIFO (read) or pushed to TFIFO (write) (410B §4.1).
    #[doc(alias("RFIFO", "TFIFO"))]
    Fifo,
    Fifo
);

word_register!(
    /// 17H PROGERR_FL (read) / CLR_PROGERR_FL (write 1 to clear) (410B §4.1). The
    /// datasheet gives no assignment of the individual error flags.
    #[doc(alias("PROGERR_FL", "CLR_PROGERR_FL"))]
    ProgerrFl,
    ProgerrFl
);
