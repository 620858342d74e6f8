//! The 8-bit host bus (BUSWIDTH = 0) over a 16-bit [`SerconBus`] (410B §2).
//!
//! On an 8-bit bus A0 selects the byte of a word; pin BYTEDIR (pin 100) says which:
//! BYTEDIR = 0 → A0 = 0 addresses the low byte (low byte first), BYTEDIR = 1 → A0 = 0
//! addresses the high byte (high byte first). The byte at A0 = 0 is the *first* byte
//! of the word, the byte at A0 = 1 the *second*.
//!
//! The chip moves whole words internally, so it latches (reading chosen, see
//! `docs/spec-notes.md`):
//!
//! * **write**: writing the first byte only stores it in a write latch; writing the
//!   second byte writes the word {latched first byte, second byte} to the word address
//!   of the second access. A lone first-byte write changes nothing; a lone second-byte
//!   write combines with whatever the latch holds (0 after construction).
//! * **read**: reading the first byte reads the whole word (with its side effects, e.g.
//!   an RFIFO pop, once) and stores the second byte in a read latch; reading the second
//!   byte returns the latch without a bus access. So a word read byte by byte is
//!   consistent even if the chip changes it between the two accesses.
//!
//! The register space and the RAM share the two latches, as one latch per direction
//! is the simplest hardware.

use crate::bus::SerconBus;

/// Level of pin BYTEDIR (410B §2, pin 100).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[doc(alias = "BYTEDIR")]
pub enum ByteDir {
    /// BYTEDIR = 0: A0 = 0 addresses the lower 8 bits (low byte first).
    #[default]
    LowFirst,
    /// BYTEDIR = 1: A0 = 0 addresses the upper 8 bits (high byte first).
    HighFirst,
}

/// An 8-bit host bus with BYTEDIR over any 16-bit [`SerconBus`].
///
/// It is itself a [`SerconBus`]: a word access becomes two byte accesses, first byte
/// (A0 = 0) then second (A0 = 1), as an 8-bit processor would make them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ByteBus<B> {
    bus: B,
    bytedir: ByteDir,
    read_latch: u8,
    write_latch: u8,
}

impl<B: SerconBus> ByteBus<B> {
    /// An 8-bit bus with pin BYTEDIR at `bytedir` over `bus`; both latches hold 0.
    pub const fn new(bus: B, bytedir: ByteDir) -> Self {
        ByteBus {
            bus,
            bytedir,
            read_latch: 0,
            write_latch: 0,
        }
    }

    /// The level of BYTEDIR.
    pub const fn bytedir(&self) -> ByteDir {
        self.bytedir
    }

    /// The 16-bit bus underneath.
    pub const fn inner(&self) -> &B {
        &self.bus
    }

    /// The 16-bit bus underneath, mutably.
    pub fn inner_mut(&mut self) -> &mut B {
        &mut self.bus
    }

    /// Gives back the 16-bit bus.
    pub fn into_inner(self) -> B {
        self.bus
    }

    /// The byte at A0 = `a0` of `word` under BYTEDIR.
    const fn byte_of(&self, word: u16, a0: bool) -> u8 {
        // 410B §2 BYTEDIR: 0 → A0 = 0 is the low byte; 1 → A0 = 0 is the high byte.
        let high = match self.bytedir {
            ByteDir::LowFirst => a0,
            ByteDir::HighFirst => !a0,
        };
        if high { (word >> 8) as u8 } else { word as u8 }
    }

    /// The word made of `first` (A0 = 0) and `second` (A0 = 1) under BYTEDIR.
    const fn word_of(&self, first: u8, second: u8) -> u16 {
        match self.bytedir {
            ByteDir::LowFirst => (second as u16) << 8 | first as u16,
            ByteDir::HighFirst => (first as u16) << 8 | second as u16,
        }
    }

    fn read_byte(&mut self, a0: bool, read_word: impl FnOnce(&mut B) -> u16) -> u8 {
        if a0 {
            self.read_latch
        } else {
            let word = read_word(&mut self.bus);
            self.read_latch = self.byte_of(word, true);
            self.byte_of(word, false)
        }
    }

    fn write_byte(&mut self, a0: bool, value: u8, write_word: impl FnOnce(&mut B, u16)) {
        if a0 {
            let word = self.word_of(self.write_latch, value);
            write_word(&mut self.bus, word);
        } else {
            self.write_latch = value;
        }
    }

    /// Reads the register byte at byte address `byte_address` (A6-0).
    pub fn read_register_byte(&mut self, byte_address: u8) -> u8 {
        let word = byte_address >> 1;
        self.read_byte(byte_address & 1 != 0, |b| b.read_register(word))
    }

    /// Writes the register byte at byte address `byte_address` (A6-0).
    pub fn write_register_byte(&mut self, byte_address: u8, value: u8) {
        let word = byte_address >> 1;
        self.write_byte(byte_address & 1 != 0, value, |b, v| {
            b.write_register(word, v)
        })
    }

    /// Reads the RAM byte at byte address `byte_address` (A11-0).
    pub fn read_ram_byte(&mut self, byte_address: u16) -> u8 {
        let word = byte_address >> 1;
        self.read_byte(byte_address & 1 != 0, |b| b.read_ram(word))
    }

    /// Writes the RAM byte at byte address `byte_address` (A11-0).
    pub fn write_ram_byte(&mut self, byte_address: u16, value: u8) {
        let word = byte_address >> 1;
        self.write_byte(byte_address & 1 != 0, value, |b, v| b.write_ram(word, v))
    }
}

impl<B: SerconBus> SerconBus for ByteBus<B> {
    fn read_register(&mut self, address: u8) -> u16 {
        let byte_address = (address & crate::register::REGISTER_ADDRESS_MASK) << 1;
        let first = self.read_register_byte(byte_address);
        let second = self.read_register_byte(byte_address | 1);
        self.word_of(first, second)
    }

    fn write_register(&mut self, address: u8, value: u16) {
        let byte_address = (address & crate::register::REGISTER_ADDRESS_MASK) << 1;
        self.write_register_byte(byte_address, self.byte_of(value, false));
        self.write_register_byte(byte_address | 1, self.byte_of(value, true));
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        // The byte address holds A15-0; the word address's top bit is beyond any RAM.
        let byte_address = address << 1;
        let first = self.read_ram_byte(byte_address);
        let second = self.read_ram_byte(byte_address | 1);
        self.word_of(first, second)
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        let byte_address = address << 1;
        self.write_ram_byte(byte_address, self.byte_of(value, false));
        self.write_ram_byte(byte_address | 1, self.byte_of(value, true));
    }
}
