//! The master synchronisation telegram (MST): ADR = 255 and one byte whose bits 2–0 are the
//! communication phase.

use core::fmt;

use crate::address::Address;

use super::field;
use super::{TelegramError, TelegramKind};

/// A communication phase, 0–4 (sercos-telegrams.md, MST: "The lower 3 bits designate the
/// SERCOS phase (0 - 4)").
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum CommunicationPhase {
    /// Phase 0.
    #[default]
    Phase0 = 0,
    /// Phase 1.
    Phase1 = 1,
    /// Phase 2.
    Phase2 = 2,
    /// Phase 3.
    Phase3 = 3,
    /// Phase 4.
    Phase4 = 4,
}

impl CommunicationPhase {
    /// All phases, 0 to 4.
    pub const ALL: [CommunicationPhase; 5] = [
        CommunicationPhase::Phase0,
        CommunicationPhase::Phase1,
        CommunicationPhase::Phase2,
        CommunicationPhase::Phase3,
        CommunicationPhase::Phase4,
    ];

    /// The phase number, 0–4.
    pub const fn number(self) -> u8 {
        self as u8
    }

    /// Whether this is a cyclic phase (3 or 4), in which the MDT is broadcast
    /// (sercos-telegrams.md, ADR: "During cyclic operations (Phases 3, 4), the Master can
    /// communicate with all drives").
    pub const fn is_cyclic(self) -> bool {
        matches!(
            self,
            CommunicationPhase::Phase3 | CommunicationPhase::Phase4
        )
    }
}

impl TryFrom<u8> for CommunicationPhase {
    type Error = TelegramError;

    fn try_from(number: u8) -> Result<Self, TelegramError> {
        match number {
            0 => Ok(CommunicationPhase::Phase0),
            1 => Ok(CommunicationPhase::Phase1),
            2 => Ok(CommunicationPhase::Phase2),
            3 => Ok(CommunicationPhase::Phase3),
            4 => Ok(CommunicationPhase::Phase4),
            other => Err(TelegramError::UnknownPhase(other)),
        }
    }
}

impl From<CommunicationPhase> for u8 {
    fn from(phase: CommunicationPhase) -> u8 {
        phase.number()
    }
}

impl fmt::Display for CommunicationPhase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "phase {}", self.number())
    }
}

/// A view of MST telegram bytes: `ADR phase`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MstPacket<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> MstPacket<T> {
    /// Wraps a buffer without checking its length. Getters on a short buffer read 0 and
    /// setters do nothing; nothing panics.
    pub const fn new_unchecked(buffer: T) -> MstPacket<T> {
        MstPacket { buffer }
    }

    /// Wraps a buffer that holds exactly the two MST bytes.
    pub fn new_checked(buffer: T) -> Result<MstPacket<T>, TelegramError> {
        let packet = MstPacket::new_unchecked(buffer);
        packet.check_len()?;
        Ok(packet)
    }

    /// Checks that the buffer is exactly ADR and the phase byte
    /// (sercos-telegrams.md, MST: "The Message Field for the MST consists of one 8-bit word").
    pub fn check_len(&self) -> Result<(), TelegramError> {
        let got = self.buffer.as_ref().len();
        TelegramError::check_at_least("MST", field::MST_LEN, got)?;
        if got > field::MST_LEN {
            Err(TelegramError::MstTooLong { got })
        } else {
            Ok(())
        }
    }

    /// The wrapped buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// The ADR byte (255 in a valid MST).
    pub fn address(&self) -> Address {
        Address::from(field::read_u8(self.buffer.as_ref(), field::ADR))
    }

    /// The whole phase byte, bits 7–3 included.
    pub fn phase_byte(&self) -> u8 {
        field::read_u8(self.buffer.as_ref(), field::MST_PHASE)
    }

    /// Bits 2–0 of the phase byte (0–7; only 0–4 are phases).
    pub fn phase_bits(&self) -> u8 {
        self.phase_byte() & MstRepr::PHASE_MASK
    }

    /// The communication phase, or [`TelegramError::UnknownPhase`] for 5–7.
    pub fn phase(&self) -> Result<CommunicationPhase, TelegramError> {
        CommunicationPhase::try_from(self.phase_bits())
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> MstPacket<T> {
    /// Sets the ADR byte.
    pub fn set_address(&mut self, address: Address) {
        field::write_u8(self.buffer.as_mut(), field::ADR, address.to_byte());
    }

    /// Sets the whole phase byte.
    pub fn set_phase_byte(&mut self, byte: u8) {
        field::write_u8(self.buffer.as_mut(), field::MST_PHASE, byte);
    }
}

/// An MST: the phase byte, kept whole.
///
/// sercos-telegrams.md, MST: only bits 2–0 carry the phase. The other bits are kept as they
/// came (the SERCON410B's PHAS0 register, which the chip sends, is 8 bits wide and resets to
/// 0FFH: 410B register 0AH), so parsing never loses them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MstRepr {
    phase_byte: u8,
}

impl MstRepr {
    /// The phase bits, 2–0 (sercos-telegrams.md, MST).
    pub const PHASE_MASK: u8 = 0b111;

    /// An MST of `phase` with the other bits 0, e.g. `FF 02` for phase 2.
    pub const fn new(phase: CommunicationPhase) -> MstRepr {
        MstRepr {
            phase_byte: phase.number(),
        }
    }

    /// An MST carrying this phase byte unchanged.
    pub const fn from_phase_byte(phase_byte: u8) -> MstRepr {
        MstRepr { phase_byte }
    }

    /// The whole phase byte.
    pub const fn phase_byte(self) -> u8 {
        self.phase_byte
    }

    /// Bits 2–0 (0–7).
    pub const fn phase_bits(self) -> u8 {
        self.phase_byte & Self::PHASE_MASK
    }

    /// Bits 7–3 in place (the byte with the phase bits cleared).
    pub const fn other_bits(self) -> u8 {
        self.phase_byte & !Self::PHASE_MASK
    }

    /// With bits 7–3 replaced by those of `bits`.
    #[must_use]
    pub const fn with_other_bits(self, bits: u8) -> MstRepr {
        MstRepr {
            phase_byte: self.phase_bits() | (bits & !Self::PHASE_MASK),
        }
    }

    /// The communication phase, or [`TelegramError::UnknownPhase`] for 5–7.
    pub fn phase(self) -> Result<CommunicationPhase, TelegramError> {
        CommunicationPhase::try_from(self.phase_bits())
    }

    /// Parses an MST view: two bytes, ADR = 255 (sercos-telegrams.md, ADR table: MST 255 in
    /// all phases).
    pub fn parse<T: AsRef<[u8]> + ?Sized>(
        packet: &MstPacket<&T>,
    ) -> Result<MstRepr, TelegramError> {
        packet.check_len()?;
        let address = packet.address();
        if !address.is_broadcast() {
            return Err(TelegramError::BadAddress {
                kind: TelegramKind::Mst,
                address,
            });
        }
        Ok(MstRepr::from_phase_byte(packet.phase_byte()))
    }

    /// The telegram length in bytes, 2.
    pub const fn buffer_len(&self) -> usize {
        field::MST_LEN
    }

    /// Writes `FF phase_byte` into a two-byte view.
    pub fn emit<T: AsRef<[u8]> + AsMut<[u8]>>(
        &self,
        packet: &mut MstPacket<T>,
    ) -> Result<(), TelegramError> {
        let got = packet.buffer.as_ref().len();
        if got != self.buffer_len() {
            return Err(TelegramError::BufferLength {
                what: "MST",
                needed: self.buffer_len(),
                got,
            });
        }
        packet.set_address(Address::Broadcast);
        packet.set_phase_byte(self.phase_byte);
        Ok(())
    }
}

impl fmt::Display for MstRepr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.phase() {
            Ok(phase) => write!(f, "MST {phase}")?,
            Err(_) => write!(f, "MST phase bits {}", self.phase_bits())?,
        }
        if self.other_bits() != 0 {
            write!(f, " (byte {:02X}H)", self.phase_byte)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phase_2_is_ff_02() {
        // sercos-telegrams.md, MST: ADR 255, bits 2–0 = phase.
        let mut bytes = [0u8; 2];
        let mut packet = MstPacket::new_checked(&mut bytes[..]).expect("2 bytes");
        MstRepr::new(CommunicationPhase::Phase2)
            .emit(&mut packet)
            .expect("fits");
        assert_eq!(bytes, [0xFF, 0x02]);
    }

    #[test]
    fn other_bits_survive() {
        let bytes = [0xFF, 0x83];
        let repr =
            MstRepr::parse(&MstPacket::new_checked(&bytes[..]).expect("2 bytes")).expect("valid");
        assert_eq!(repr.phase(), Ok(CommunicationPhase::Phase3));
        assert_eq!(repr.other_bits(), 0x80);
        assert_eq!(repr.phase_byte(), 0x83);
    }
}
