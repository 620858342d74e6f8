//! The service-channel bits of a data record's first word: the MDT control word bits
//! 5–0 and the AT status word bits 2–0 and 5 (sercos-telegrams.md; ERRATA "service info
//! in a container"). Every other bit of the word belongs to the host and is kept.

use sercos_wire::telegram::{ControlWord, StatusWord};

/// The service-channel bits of an MDT control word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct MdtService {
    /// Bit 0: MHS, the master's handshake toggle bit.
    pub(super) mhs: bool,
    /// Bit 1: 0 read, 1 write service info.
    pub(super) write: bool,
    /// Bit 2: last transmission.
    pub(super) last: bool,
    /// Bits 5–3: data block element.
    pub(super) element: u8,
}

/// Bits 5–0 of the MDT control word.
const MDT_SERVICE_BITS: u16 = ControlWord::MHS
    | ControlWord::WRITE
    | ControlWord::LAST_TRANSMISSION
    | ControlWord::DATA_BLOCK_ELEMENT;

impl MdtService {
    /// Takes the bits out of a received control word.
    pub(super) fn from_word(word: u16) -> Self {
        // sercos-telegrams.md, MDT control word: bit 0 MHS, 1 R/W, 2 last, 5-3 element.
        MdtService {
            mhs: word & ControlWord::MHS != 0,
            write: word & ControlWord::WRITE != 0,
            last: word & ControlWord::LAST_TRANSMISSION != 0,
            element: ((word & ControlWord::DATA_BLOCK_ELEMENT) >> 3) as u8,
        }
    }

    /// `word` with bits 5–0 replaced by these bits.
    pub(super) fn put_into(self, word: u16) -> u16 {
        (word & !MDT_SERVICE_BITS)
            | u16::from(self.mhs)
            | u16::from(self.write) << 1
            | u16::from(self.last) << 2
            | (u16::from(self.element) & 7) << 3
    }
}

/// The service-channel bits of an AT status word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct AtService {
    /// Bit 0: AHS, the slave's handshake toggle bit.
    pub(super) ahs: bool,
    /// Bit 1: busy, step in progress.
    pub(super) busy: bool,
    /// Bit 2: error in service channel.
    pub(super) error: bool,
    /// Bit 5: change bit commands (CMD_AT in the container).
    pub(super) command_change: bool,
}

/// Bits 0, 1, 2 and 5 of the AT status word.
const AT_SERVICE_BITS: u16 = StatusWord::AHS
    | StatusWord::BUSY
    | StatusWord::SERVICE_CHANNEL_ERROR
    | StatusWord::COMMAND_CHANGE;

impl AtService {
    /// Takes the bits out of a received status word.
    pub(super) fn from_word(word: u16) -> Self {
        // sercos-telegrams.md, AT status word: bit 0 AHS, 1 busy, 2 error, 5 command change.
        AtService {
            ahs: word & StatusWord::AHS != 0,
            busy: word & StatusWord::BUSY != 0,
            error: word & StatusWord::SERVICE_CHANNEL_ERROR != 0,
            command_change: word & StatusWord::COMMAND_CHANGE != 0,
        }
    }

    /// `word` with bits 0, 1, 2 and 5 replaced by these bits.
    pub(super) fn put_into(self, word: u16) -> u16 {
        (word & !AT_SERVICE_BITS)
            | u16::from(self.ahs)
            | u16::from(self.busy) << 1
            | u16::from(self.error) << 2
            | u16::from(self.command_change) << 5
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // sercos-telegrams.md MDT control word bits 5-0; ERRATA "service info in a container".
    #[test]
    fn mdt_bits_round_trip_and_keep_host_bits() {
        // element 101, last 1, write 0, MHS 1.
        let word = 0xE000 | 0b10_1101;
        let bits = MdtService::from_word(word);
        assert_eq!(
            bits,
            MdtService {
                mhs: true,
                write: false,
                last: true,
                element: 5
            }
        );
        assert_eq!(bits.put_into(0xE000 | 0x3F), word);
    }

    // sercos-telegrams.md AT status word bits 0-2 and 5.
    #[test]
    fn at_bits_round_trip_and_keep_host_bits() {
        let word = 0xC018 | 0b10_0110;
        let bits = AtService::from_word(word);
        assert!(!bits.ahs && bits.busy && bits.error && bits.command_change);
        assert_eq!(bits.put_into(0xC018 | 0x27), word);
    }
}
