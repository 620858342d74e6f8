//! The host-bus interface of the controller as a driver sees it (410B §2, §3.4).

use crate::Variant;
use crate::error::RamError;
use crate::ram::header::{Header, HeaderKind};
use crate::register::Register;
use crate::value::interrupt::{IntFlagsHi, IntFlagsLo};
use crate::value::{RegisterValue, Version};

/// 16-bit access to the controller's control registers and dual-port RAM.
///
/// This is the chip's host interface (410B §2): a register is selected by its word
/// address on A6-1 with PCSN0/PCS1, a RAM word by its word address on A10-1 (410B) or
/// A11-1 (816 §2.5) with MCSN0/1. The chip model implements it, and so does a driver's
/// wrapper around a real chip mapped into memory.
///
/// Contract for implementations (no method may panic, whatever the arguments):
///
/// * register addresses: only the low 6 bits are decoded (A6-1), so `address` is
///   reduced with `address & 0x3F`; addresses without a register read 0 and ignore
///   writes (410B §4.1);
/// * RAM addresses: only the variant's address bits are decoded, so `address` is
///   *masked* with [`Variant::ram_address_mask`] (it wraps; nothing is ignored);
/// * reads take `&mut self` because they can have side effects: reading 27H pops RFIFO.
pub trait SerconBus {
    /// Reads the control register at word address `address` (00H–3FH).
    fn read_register(&mut self, address: u8) -> u16;
    /// Writes `value` to the control register at word address `address` (00H–3FH).
    fn write_register(&mut self, address: u8, value: u16);
    /// Reads the RAM word at word address `address`.
    fn read_ram(&mut self, address: u16) -> u16;
    /// Writes `value` to the RAM word at word address `address`.
    fn write_ram(&mut self, address: u16, value: u16);
}

impl<B: SerconBus + ?Sized> SerconBus for &mut B {
    fn read_register(&mut self, address: u8) -> u16 {
        (**self).read_register(address)
    }
    fn write_register(&mut self, address: u8, value: u16) {
        (**self).write_register(address, value)
    }
    fn read_ram(&mut self, address: u16) -> u16 {
        (**self).read_ram(address)
    }
    fn write_ram(&mut self, address: u16, value: u16) {
        (**self).write_ram(address, value)
    }
}

/// Register values that can be read, changed and written back without side effects:
/// no write-1-to-clear flags, no write actions that read back as a status.
///
/// Not implemented for 4H/5H and 17H (writing back the flags read would clear them),
/// 27H (a read pops RFIFO), 28H (INT_WDOG/INT_RSCEND read as 1 would clear) and 29H.
pub trait Modifiable: RegisterValue {}

macro_rules! modifiable {
    ($($ty:path),* $(,)?) => { $( impl Modifiable for $ty {} )* };
}
modifiable!(
    crate::value::control::Ctrl1,
    crate::value::control::Ctrl2,
    crate::value::control::Ctrl3,
    crate::value::control::Ctrl0C,
    crate::value::interrupt::En0IntLo,
    crate::value::interrupt::En0IntHi,
    crate::value::interrupt::En1IntLo,
    crate::value::interrupt::En1IntHi,
    crate::value::timing::Phas,
    crate::value::timing::ScTimeout,
    crate::value::timing::MclkDiv,
    crate::value::timing::Ndivclk,
    crate::value::timing::Tscyc0,
    crate::value::timing::Tscyc1,
    crate::value::timing::Tcntst,
    crate::value::timing::Tcycstart,
    crate::value::timing::Jtscyc1,
    crate::value::timing::Jtscyc2,
    crate::value::timing::Jtrdel1,
    crate::value::timing::Jtrdel2,
    crate::value::timing::Tint0,
    crate::value::timing::Tint1,
    crate::value::timing::Tint2,
    crate::value::timing::Tint3,
    crate::value::timing::Tdivclk,
    crate::value::timing::Dtdivclk,
    crate::value::pointer::Thrpt,
    crate::value::watchdog::Twdog,
);

/// Typed conveniences over any [`SerconBus`] (implemented for all of them).
pub trait SerconBusExt: SerconBus {
    /// Reads `register` as a raw word.
    fn read(&mut self, register: Register) -> u16 {
        self.read_register(register.address())
    }

    /// Writes a raw word to `register`.
    fn write(&mut self, register: Register, value: u16) {
        self.write_register(register.address(), value)
    }

    /// Reads the register of `R` as a typed value, e.g. `bus.read_reg::<Ctrl1>()`.
    fn read_reg<R: RegisterValue>(&mut self) -> R {
        R::from_bits(self.read_register(R::REGISTER.address()))
    }

    /// Writes a typed value to its register, e.g. `bus.write_reg(Phas::new(4, 4))`.
    fn write_reg<R: RegisterValue>(&mut self, value: R) {
        self.write_register(R::REGISTER.address(), value.bits())
    }

    /// Reads the register of `R`, applies `f` and writes the result back.
    fn modify_reg<R: Modifiable>(&mut self, f: impl FnOnce(R) -> R) {
        let value = self.read_reg::<R>();
        self.write_reg(f(value));
    }

    /// Clears the interrupt flags `flags` of 4H (write 1 to clear, ERRATA "410B 4H/5H").
    fn clear_int_lo(&mut self, flags: IntFlagsLo) {
        self.write_reg(flags)
    }

    /// Clears the interrupt flags `flags` of 5H (write 1 to clear, ERRATA "410B 4H/5H").
    fn clear_int_hi(&mut self, flags: IntFlagsHi) {
        self.write_reg(flags)
    }

    /// The variant identified by register VERSION (816 §2.11.1.1), if known.
    fn detect_variant(&mut self) -> Option<Variant> {
        self.read_reg::<Version>().variant()
    }

    /// Reads `N` consecutive RAM words starting at `address` (addresses wrap).
    fn read_ram_words<const N: usize>(&mut self, address: u16) -> [u16; N] {
        let mut out = [0u16; N];
        let mut a = address;
        for word in &mut out {
            *word = self.read_ram(a);
            a = a.wrapping_add(1);
        }
        out
    }

    /// Writes `words` to consecutive RAM words starting at `address` (addresses wrap).
    fn write_ram_words(&mut self, address: u16, words: &[u16]) {
        let mut a = address;
        for word in words {
            self.write_ram(a, *word);
            a = a.wrapping_add(1);
        }
    }

    /// Reads and decodes the header or end marker at `address` (410B §4.2.1, §4.2.3):
    /// word 0 is read first and only as many words as its marker bits call for.
    fn read_header(&mut self, variant: Variant, address: u16) -> Result<Header, RamError> {
        let word0 = self.read_ram(address);
        let kind = HeaderKind::classify(word0)?;
        let mut words = [word0, 0, 0, 0, 0];
        let mut a = address;
        for word in words.iter_mut().take(kind.words()).skip(1) {
            a = a.wrapping_add(1);
            *word = self.read_ram(a);
        }
        Header::decode(variant, &words)
    }

    /// Encodes and writes a header or end marker at `address`.
    fn write_header(&mut self, variant: Variant, address: u16, header: &Header) {
        let mut words = [0u16; 5];
        // 5 words fit every kind of header, so encoding cannot fail here.
        let n = header.encode(variant, &mut words).unwrap_or(0);
        if let Some(words) = words.get(..n) {
            self.write_ram_words(address, words);
        }
    }
}

impl<B: SerconBus + ?Sized> SerconBusExt for B {}
