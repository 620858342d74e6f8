//! The records the slave exchanges: its MDT record (command values) out of the receive
//! container, its AT record (status word and feedback) into the transmit container, with
//! the buffering of 410B §4.2.1 / §4.2.2.

use sercon_regs::SerconBus;
use sercon_regs::ram::header::Buffering;

use crate::ram_layout::{ContainerPlace, PhaseGroup, RamLayout};
use sercon_regs::ram::header::HeaderKind;

/// 410B §4.2.1 header word 0 bit 10: VAL.
const VAL: u16 = 1 << 10;
/// 410B §4.2.1 receive header word 0 bit 13: RERR.
const RERR: u16 = 1 << 13;

/// Where the slave's two records of one transmission block live.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RecordPlaces {
    /// Header of the slave's AT (transmit).
    pub at_header: u16,
    /// Its container (the status word is data word 0).
    pub at: ContainerPlace,
    /// Header of the MDT the slave receives.
    pub mdt_header: u16,
    /// Its receive container (the control word is data word 0).
    pub mdt: ContainerPlace,
}

impl RecordPlaces {
    /// The AT and MDT of the block serving `group` in `layout`, if laid out.
    pub fn find(layout: &RamLayout, group: PhaseGroup) -> Option<RecordPlaces> {
        let block = layout.map.blocks.iter().find(|b| b.group == group)?;
        let at = block
            .telegrams
            .iter()
            .find(|t| t.kind == HeaderKind::Transmit)?;
        let mdt = block
            .telegrams
            .iter()
            .find(|t| t.kind == HeaderKind::Receive)?;
        Some(RecordPlaces {
            at_header: at.header,
            at: *at.containers.first()?,
            mdt_header: mdt.header,
            mdt: *mdt.containers.first()?,
        })
    }

    /// The MDT record received last, as line bytes (little endian), if the last telegram
    /// was received free of error (410B §4.2.1 RERR = 0) and its data are valid (single
    /// buffer VAL = 1; double buffer: VAL names the valid buffer).
    pub fn read_command<B: SerconBus + ?Sized>(&self, bus: &mut B) -> Option<Vec<u8>> {
        let mut bytes = Vec::with_capacity(usize::from(self.mdt.len) * 2);
        self.read_command_into(bus, &mut bytes).then_some(bytes)
    }

    /// [`read_command`](Self::read_command) into `bytes` (cleared first, its allocation
    /// reused); `false` when there is no valid record.
    pub fn read_command_into<B: SerconBus + ?Sized>(
        &self,
        bus: &mut B,
        bytes: &mut Vec<u8>,
    ) -> bool {
        bytes.clear();
        let word0 = bus.read_ram(self.mdt_header);
        // 410B §4.2.1 RERR: "errored or not received (RERR = 1)".
        if word0 & RERR != 0 {
            return false;
        }
        let start = match self.mdt.buffering {
            // 410B §4.2.1 VAL, single buffer: "telegram data is invalid (VAL = 0) or valid".
            Buffering::Single if word0 & VAL != 0 => self.mdt.data,
            // 410B §4.2.1 VAL, double buffer: "data in buffer 0 (VAL = 0) or buffer 1
            // (VAL = 1) is valid"; buffer 1 follows buffer 0 (ERRATA "container words").
            Buffering::Double if word0 & VAL != 0 => self.mdt.data.wrapping_add(self.mdt.len),
            Buffering::Double => self.mdt.data,
            _ => return false,
        };
        for i in 0..self.mdt.len {
            bytes.extend_from_slice(&bus.read_ram(start.wrapping_add(i)).to_le_bytes());
        }
        true
    }

    /// Writes the AT record: status word and feedback data; the service info (data
    /// word 1) belongs to the chip's service container (ERRATA "service info in a container")
    /// and is left alone. With a double buffer the words go to the buffer not in use and
    /// VAL is toggled (410B §4.2.1 transmit VAL "Set by processor").
    pub fn write_feedback<B: SerconBus + ?Sized>(
        &self,
        bus: &mut B,
        status_word: u16,
        feedback: &[u8],
    ) {
        self.write_feedback_changed(bus, status_word, feedback, &mut AtWritten::default());
    }

    /// [`write_feedback`](Self::write_feedback), writing into a single buffer only the
    /// words that differ from what `written` says the driver wrote there last (and noting
    /// what it writes). Only the processor writes a transmit container's data words: the
    /// chip fills the service bits and info into the telegram it sends, not into the RAM
    /// (410B §4.2.2 SVFL; ERRATA "service info in a container"), so a word written once
    /// holds until the driver writes it again or the RAM is laid out anew (then `written`
    /// starts empty). A double buffer is written in full every cycle (the other buffer).
    pub(crate) fn write_feedback_changed<B: SerconBus + ?Sized>(
        &self,
        bus: &mut B,
        status_word: u16,
        feedback: &[u8],
        written: &mut AtWritten,
    ) {
        let (start, toggle, word0) = match self.at.buffering {
            Buffering::Single => (self.at.data, false, 0),
            Buffering::Double => {
                let word0 = bus.read_ram(self.at_header);
                if word0 & VAL != 0 {
                    (self.at.data, true, word0)
                } else {
                    (self.at.data.wrapping_add(self.at.len), true, word0)
                }
            }
            Buffering::Dma => return,
        };
        if toggle {
            // Both buffers take turns: nothing written before is known to be there.
            written.forget();
        }
        written.write(bus, start, 0, status_word);
        if toggle {
            // Keep the service info the chip last sent in the other buffer.
            let other = if start == self.at.data {
                self.at.data.wrapping_add(self.at.len)
            } else {
                self.at.data
            };
            let service = bus.read_ram(other.wrapping_add(1));
            bus.write_ram(start.wrapping_add(1), service);
        }
        let data_words = self.at.len.saturating_sub(2);
        let mut chunks = feedback.chunks(2);
        for i in 0..data_words {
            let word = match chunks.next() {
                Some([low, high]) => u16::from_le_bytes([*low, *high]),
                Some([low]) => u16::from(*low),
                _ => 0,
            };
            written.write(bus, start, 2u16.wrapping_add(i), word);
        }
        if toggle {
            bus.write_ram(self.at_header, word0 ^ VAL);
            written.forget();
        }
    }
}

/// The words the driver last wrote into a single-buffered AT container, by data word
/// offset (`None`: not known), so that a cycle writes only the words that changed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct AtWritten {
    words: Vec<Option<u16>>,
}

impl AtWritten {
    /// Nothing written is known any more.
    pub(crate) fn forget(&mut self) {
        self.words.clear();
    }

    /// Writes `word` at data word `offset` of the buffer at `start` unless it is known to
    /// be there already.
    fn write<B: SerconBus + ?Sized>(&mut self, bus: &mut B, start: u16, offset: u16, word: u16) {
        let i = usize::from(offset);
        if self.words.get(i).copied().flatten() == Some(word) {
            return;
        }
        bus.write_ram(start.wrapping_add(offset), word);
        if self.words.len() <= i {
            self.words.resize(i + 1, None);
        }
        if let Some(slot) = self.words.get_mut(i) {
            *slot = Some(word);
        }
    }
}
