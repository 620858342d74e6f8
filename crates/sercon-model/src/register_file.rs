//! The stored R/W bits of the control registers and the generic bus semantics of
//! 410B §4.1, driven by the access table of sercon-regs.
//!
//! 410B §4.1: "All control registers can be written to and read (R/W), with the exception
//! of the control bits that initiate an action (W). The status registers can only be read
//! (R). [...] If control registers are read with bits that are not used, these bits are
//! set to 0."

use sercon_regs::{Register, RegisterSpec, Variant, register_spec};

use crate::Straps;
use crate::serial_settings::repon_reset;

/// Number of word addresses decoded by A6-1 (410B §2).
const WORDS: usize = sercon_regs::register::REGISTER_SPACE_WORDS;

/// What a bus write asks of the chip beyond storing its R/W bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct WriteRequest {
    /// The register written, if the address decodes to one on this variant.
    pub(crate) register: Option<Register>,
    /// Bits written as 1 among the write-1-to-clear flags.
    pub(crate) clear: u16,
    /// The written value restricted to the write-action bits.
    pub(crate) actions: u16,
}

/// The R/W words of the register space (status bits are not stored here).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct RegisterFile {
    variant: Variant,
    words: [u16; WORDS],
}

impl RegisterFile {
    /// The register file after a reset (RSTN or SWRST).
    // 410B §4.1: reset values in bold; 816 §2.3.3: REPON after reset from TM0-1.
    pub(crate) fn after_reset(variant: Variant, straps: &Straps) -> Self {
        let mut words = [0u16; WORDS];
        for (address, word) in (0u8..).zip(words.iter_mut()) {
            let spec = register_spec(variant, address);
            *word = spec.reset & spec.rw;
        }
        let mut file = RegisterFile { variant, words };
        // 816 §2.3.3: "The reset value of the control bit [REPON, 1H.3] can be
        // determined by the pins TM0-1".
        let repon = repon_reset(variant, straps);
        let c1 = file.stored(Register::Ctrl1);
        file.set_stored(Register::Ctrl1, (c1 & !(1 << 3)) | (u16::from(repon) << 3));
        file
    }

    fn spec(&self, address: u8) -> RegisterSpec {
        register_spec(self.variant, address)
    }

    /// The stored R/W bits of `register`.
    pub(crate) fn stored(&self, register: Register) -> u16 {
        self.words
            .get(usize::from(register.address()))
            .copied()
            .unwrap_or(0)
    }

    /// Overwrites the stored R/W bits of `register` (chip-internal changes such as the
    /// watchdog clearing ENTMT); bits that are not R/W are dropped.
    pub(crate) fn set_stored(&mut self, register: Register, value: u16) {
        let rw = self.spec(register.address()).rw;
        if let Some(word) = self.words.get_mut(usize::from(register.address())) {
            *word = value & rw;
        }
    }

    /// The value a bus read of `address` returns given the chip's status bits.
    pub(crate) fn read(&self, address: u8, status: u16) -> u16 {
        let address = address & sercon_regs::register::REGISTER_ADDRESS_MASK;
        let stored = self.words.get(usize::from(address)).copied().unwrap_or(0);
        // 410B §4.1: unused bits read 0; R/W bits read back; status bits come from the chip.
        self.spec(address).read_value(stored, status)
    }

    /// Applies the R/W part of a bus write, except for the bits in `locked` which keep
    /// their value, and returns what else the write asks for.
    pub(crate) fn write(&mut self, address: u8, value: u16, locked: u16) -> WriteRequest {
        let address = address & sercon_regs::register::REGISTER_ADDRESS_MASK;
        let spec = self.spec(address);
        if let Some(word) = self.words.get_mut(usize::from(address)) {
            // 410B §4.1: bits that are read-only or unused "can be set to 0 or 1; they
            // are not evaluated internally".
            let stored = spec.stored_after_write(*word, value);
            *word = (stored & !locked) | (*word & locked);
        }
        WriteRequest {
            register: Register::from_address(address).filter(|r| r.exists_on(self.variant)),
            clear: value & spec.w1c,
            actions: value & spec.write_action,
        }
    }
}
