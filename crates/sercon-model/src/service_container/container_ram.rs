//! Bounded access to one service container in the dual-port RAM.
//!
//! Every address is formed the way the chip forms it: SCPTn (410B §4.2, words 2–9) masked
//! to the variant's pointer width, plus an 8-bit offset, wrapped within the RAM
//! (`sercon_regs::ram::service::sc_word_address`). A RAM slice shorter than the variant's
//! RAM reads 0 and ignores writes beyond its end, so no RAM content can make an access
//! leave the slice.

use sercon_regs::Variant;
use sercon_regs::ram::service::{SC_BUFFER_OFFSET, SC_CONTROL_WORDS, sc_word_address};
use sercon_regs::ram::{SCPT0, scpt};

/// One service container: where it starts and how many RAM words were touched.
pub(super) struct ContainerRam<'a> {
    ram: &'a mut [u16],
    variant: Variant,
    base: u16,
    accesses: u16,
}

impl<'a> ContainerRam<'a> {
    /// Container `nsv` (only its 3 bits count, as NSV in the data container, 410B
    /// §4.2.2): reads SCPTn.
    pub(super) fn locate(ram: &'a mut [u16], variant: Variant, nsv: u8) -> Self {
        // 410B §4.2: words 2-9 are SCPT0-7, the addresses of service containers 0-7.
        let pointer_word = scpt(nsv & 7).unwrap_or(SCPT0);
        let mut this = ContainerRam {
            ram,
            variant,
            base: 0,
            accesses: 0,
        };
        // ERRATA "word addresses": SCPTn is a word address, 10 bits (410B) / 11 bits (816).
        this.base = this.read_address(pointer_word) & variant.pointer_mask();
        this
    }

    fn read_address(&mut self, address: u16) -> u16 {
        self.accesses = self.accesses.saturating_add(1);
        let address = address & self.variant.ram_address_mask();
        self.ram.get(usize::from(address)).copied().unwrap_or(0)
    }

    fn write_address(&mut self, address: u16, value: u16) {
        self.accesses = self.accesses.saturating_add(1);
        let address = address & self.variant.ram_address_mask();
        if let Some(slot) = self.ram.get_mut(usize::from(address)) {
            *slot = value;
        }
    }

    /// The word at `offset` from SCPTn.
    fn read(&mut self, offset: u8) -> u16 {
        self.read_address(sc_word_address(self.variant, self.base, offset))
    }

    /// Writes the word at `offset` from SCPTn.
    fn write(&mut self, offset: u8, value: u16) {
        self.write_address(sc_word_address(self.variant, self.base, offset), value);
    }

    /// The five control words (410B §4.2.4: "A service container contains 5 control
    /// words and a buffer").
    pub(super) fn controls(&mut self) -> [u16; SC_CONTROL_WORDS] {
        [
            self.read(0),
            self.read(1),
            self.read(2),
            self.read(3),
            self.read(4),
        ]
    }

    /// Writes back the control words that differ from `before` (the chip writes only
    /// what it changed: spec-notes "Service containers", write-back).
    pub(super) fn store_controls(
        &mut self,
        before: [u16; SC_CONTROL_WORDS],
        after: [u16; SC_CONTROL_WORDS],
    ) {
        for (offset, (old, new)) in (0u8..).zip(before.iter().zip(after.iter())) {
            if old != new {
                self.write(offset, *new);
            }
        }
    }

    /// The buffer word at `position` (an offset from SCPTn); positions below the buffer
    /// (the control words) read 0 (spec-notes "Service containers", buffer bounds).
    pub(super) fn buffer_word(&mut self, position: u8) -> u16 {
        if position < SC_BUFFER_OFFSET {
            0
        } else {
            self.read(position)
        }
    }

    /// Writes the buffer word at `position` and says whether it did; positions below the
    /// buffer are ignored so that data never overwrites the control words.
    pub(super) fn set_buffer_word(&mut self, position: u8, value: u16) -> bool {
        let inside = position >= SC_BUFFER_OFFSET;
        if inside {
            self.write(position, value);
        }
        inside
    }

    /// RAM words read or written so far.
    pub(super) fn accesses(&self) -> u16 {
        self.accesses
    }
}
