//! Where a service container lives and how the host reaches its words over the bus.
//!
//! A service container is five control words followed by its buffer (410B §4.2.4: "A service
//! container contains 5 control words and a buffer (BUFLEN words, max. length 255)"). SCPTn,
//! RAM word 2 + n, holds its word address (410B §4.2; ERRATA "word addresses"), and the
//! buffer pointers are 8-bit offsets from that address, so the buffer starts at offset 5
//! (`sercon_regs::ram::SC_BUFFER_OFFSET`). Addresses wrap in the RAM as the chip forms them
//! (`sc_word_address`).

use sercon_regs::SerconBus;
use sercon_regs::Variant;
use sercon_regs::ram::scpt;
use sercon_regs::ram::service::{
    NInfo, SC_BUFFER_MAX_WORDS, SC_BUFFER_OFFSET, ScMaster, ScSlave, sc_word_address,
};

/// Offset of the first buffer word (410B §4.2.4, regs reading: after the 5 control words).
pub(super) const BUF: u8 = SC_BUFFER_OFFSET;

/// A service container can't be placed as asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum SlotError {
    /// NSV is 3 bits: containers 0–7 (410B §4.2, SCPT0–7).
    #[error("service container {0} does not exist (0-7)")]
    NoSuchContainer(u8),
    /// The buffer holds 1 to 251 words (8-bit offsets 5..=255).
    #[error("service container buffer of {0} words (1-251)")]
    BufferLength(u16),
    /// The container's address does not fit the variant's pointer width.
    #[error("service container address {0:#06X} outside the RAM")]
    Address(u16),
}

/// One service container as the driver uses it: which one (NSV), where it starts, how long
/// its buffer is and how many info words a record carries.
///
/// The RAM layout is somebody else's: the driver takes these as parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContainerSlot {
    variant: Variant,
    nsv: u8,
    address: u16,
    buffer_words: u8,
    ninfo: NInfo,
}

impl ContainerSlot {
    /// Service container `nsv` (0–7) at word address `address` with `buffer_words` buffer
    /// words (1–251) and one info word per record (SERCOS II).
    pub fn new(
        variant: Variant,
        nsv: u8,
        address: u16,
        buffer_words: u16,
    ) -> Result<ContainerSlot, SlotError> {
        // 410B §4.2: SCPT0-7, so NSV is 0-7.
        if nsv > 7 {
            return Err(SlotError::NoSuchContainer(nsv));
        }
        // 410B §4.2.4: buffer pointers are 8 bits, the buffer starts after 5 control words.
        let buffer = u8::try_from(buffer_words)
            .ok()
            .filter(|b| *b >= 1 && u16::from(*b) <= SC_BUFFER_MAX_WORDS)
            .ok_or(SlotError::BufferLength(buffer_words))?;
        // ERRATA "word addresses": 10-bit (410B) or 11-bit (816) pointers.
        if address & !variant.pointer_mask() != 0 {
            return Err(SlotError::Address(address));
        }
        Ok(ContainerSlot {
            variant,
            nsv,
            address,
            buffer_words: buffer,
            ninfo: NInfo::from_code(0),
        })
    }

    /// The same slot with `ninfo` info words per record (410B §4.2.4 NINFO_WRITE /
    /// NINFO_READ, 1 to 4; it must match the data containers' NINFO).
    pub fn with_ninfo(mut self, ninfo: NInfo) -> ContainerSlot {
        self.ninfo = ninfo;
        self
    }

    /// The controller variant (RAM size, pointer width).
    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// NSV: the container's number, 0–7.
    #[doc(alias = "NSV")]
    pub fn nsv(&self) -> u8 {
        self.nsv
    }

    /// Word address of the container's first control word (the value of SCPTn).
    pub fn address(&self) -> u16 {
        self.address
    }

    /// Buffer length in words.
    pub fn buffer_words(&self) -> u8 {
        self.buffer_words
    }

    /// Info words per record.
    pub fn ninfo(&self) -> NInfo {
        self.ninfo
    }

    /// Buffer words one fill moves: the buffer length rounded down to whole steps of NINFO
    /// words (at least one step, or the buffer if it is shorter), because the chip moves
    /// the pointers by NINFO per step (410B §4.2.4 NINFO; spec-notes "Service containers").
    pub fn step_capacity(&self) -> usize {
        let buffer = usize::from(self.buffer_words);
        let step = usize::from(self.ninfo.count());
        if buffer >= step {
            buffer - buffer % step
        } else {
            buffer
        }
    }

    /// Offset of the last word of [`step_capacity`](Self::step_capacity) words.
    pub(super) fn step_last(&self) -> u8 {
        let count = u8::try_from(self.step_capacity()).unwrap_or(u8::MAX);
        BUF.saturating_add(count.saturating_sub(1))
    }

    /// Offset of the last buffer word.
    pub(super) fn buffer_last(&self) -> u8 {
        // buffer_words ≤ 251, so 5 + 251 − 1 = 255 fits.
        BUF.saturating_add(self.buffer_words.saturating_sub(1))
    }

    /// Writes SCPTn (RAM word 2 + n, 410B §4.2) with the container's address.
    pub fn install<B: SerconBus + ?Sized>(&self, bus: &mut B) {
        if let Some(pointer) = scpt(self.nsv) {
            bus.write_ram(pointer, self.address);
        }
    }

    fn word_address(&self, offset: u8) -> u16 {
        sc_word_address(self.variant, self.address, offset)
    }

    /// The five control words (410B §4.2.4).
    pub(super) fn controls<B: SerconBus + ?Sized>(&self, bus: &mut B) -> [u16; 5] {
        let mut words = [0u16; 5];
        for (offset, word) in (0u8..).zip(words.iter_mut()) {
            *word = bus.read_ram(self.word_address(offset));
        }
        words
    }

    /// Control word `index` (0-4, 410B §4.2.4).
    pub(super) fn control_word<B: SerconBus + ?Sized>(&self, bus: &mut B, index: u8) -> u16 {
        bus.read_ram(self.word_address(index))
    }

    /// Writes control word `index` (0-4, 410B §4.2.4) alone.
    pub(super) fn write_control_word<B: SerconBus + ?Sized>(
        &self,
        bus: &mut B,
        index: u8,
        word: u16,
    ) {
        bus.write_ram(self.word_address(index), word);
    }

    /// The control words in master mode, word 0 already read as `word0` (words 1-4 read
    /// now).
    pub(super) fn master_after<B: SerconBus + ?Sized>(&self, bus: &mut B, word0: u16) -> ScMaster {
        let mut words = [word0, 0, 0, 0, 0];
        for (offset, word) in (1u8..).zip(words.iter_mut().skip(1)) {
            *word = bus.read_ram(self.word_address(offset));
        }
        ScMaster::from_words(words)
    }

    /// The control words in master mode.
    pub(super) fn master<B: SerconBus + ?Sized>(&self, bus: &mut B) -> ScMaster {
        ScMaster::from_words(self.controls(bus))
    }

    /// The control words in slave mode.
    pub(super) fn slave<B: SerconBus + ?Sized>(&self, bus: &mut B) -> ScSlave {
        ScSlave::from_words(self.controls(bus))
    }

    /// Writes the host's control words: the pointers (words 2, 3), word 4 when `word4`, and
    /// word 0 last, so that clearing M_BUSY / BUSY_AT releases a container that is already
    /// set up. Word 1 holds what the chip took from the line and is never written.
    pub(super) fn store<B: SerconBus + ?Sized>(&self, bus: &mut B, words: [u16; 5], word4: bool) {
        let [w0, _, w2, w3, w4] = words;
        bus.write_ram(self.word_address(2), w2);
        bus.write_ram(self.word_address(3), w3);
        if word4 {
            bus.write_ram(self.word_address(4), w4);
        }
        bus.write_ram(self.word_address(0), w0);
    }

    /// Writes all five control words (initialisation only).
    pub(super) fn store_all<B: SerconBus + ?Sized>(&self, bus: &mut B, words: [u16; 5]) {
        for (offset, word) in (0u8..).zip(words) {
            bus.write_ram(self.word_address(offset), word);
        }
    }

    /// Buffer words from offset `from` on, `count` of them (offsets stop at 255).
    pub(super) fn read_buffer<B: SerconBus + ?Sized>(
        &self,
        bus: &mut B,
        from: u8,
        count: usize,
    ) -> Vec<u16> {
        (usize::from(from)..=255)
            .take(count)
            .filter_map(|offset| u8::try_from(offset).ok())
            .map(|offset| bus.read_ram(self.word_address(offset)))
            .collect()
    }

    /// Writes `words` into the buffer from offset `from` on (offsets stop at 255).
    pub(super) fn write_buffer<B: SerconBus + ?Sized>(&self, bus: &mut B, from: u8, words: &[u16]) {
        for (offset, word) in (usize::from(from)..=255).zip(words) {
            if let Ok(offset) = u8::try_from(offset) {
                bus.write_ram(self.word_address(offset), *word);
            }
        }
    }

    /// The buffer word at `offset` (for an error code at RDDATPT).
    pub(super) fn buffer_word<B: SerconBus + ?Sized>(&self, bus: &mut B, offset: u8) -> u16 {
        bus.read_ram(self.word_address(offset))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // 410B §4.2.4: buffer max. 255 with 8-bit pointers; regs: offsets 5..=255 = 251 words.
    #[test]
    fn slot_limits() {
        let v = Variant::Sercon410b;
        assert_eq!(
            ContainerSlot::new(v, 8, 0x100, 10),
            Err(SlotError::NoSuchContainer(8))
        );
        assert_eq!(
            ContainerSlot::new(v, 0, 0x100, 0),
            Err(SlotError::BufferLength(0))
        );
        assert_eq!(
            ContainerSlot::new(v, 0, 0x100, 252),
            Err(SlotError::BufferLength(252))
        );
        assert!(ContainerSlot::new(v, 0, 0x100, 251).is_ok());
        // 410B: 10-bit pointers; 816: 11 bits.
        assert_eq!(
            ContainerSlot::new(v, 0, 0x400, 10),
            Err(SlotError::Address(0x400))
        );
        assert!(ContainerSlot::new(Variant::Sercon816, 0, 0x400, 10).is_ok());
        let slot = ContainerSlot::new(v, 7, 0x3F0, 251).expect("valid");
        assert_eq!(slot.buffer_last(), 255);
    }
}
