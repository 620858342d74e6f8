//! The master data telegram (MDT).
//!
//! sercos-telegrams.md, Master Data Telegram: in phases 0–2 the MDT is addressed to one drive
//! and its message field is one data record; in phases 3 and 4 it is broadcast (ADR 255) and
//! holds one data record per drive, each at the byte offset the master wrote into that drive's
//! S-0-0009 during phase 2.
//!
//! **Offsets.** Every `offset` in this module counts bytes from the first byte after ADR (the
//! first byte of the message field): the first record of a broadcast MDT is at offset 0.
//! sercos-facts.md reads S-0-0009 as counted "from the address field"; converting between the
//! two is left to whoever reads S-0-0009 (see docs/spec-notes.md, "Telegram formats").

use crate::address::{Address, DriveAddress};

use super::data_record::{self, DataRecord, MdtRecordRepr};
use super::field::{self, record};
use super::{TelegramError, TelegramKind};

/// The smallest MDT: ADR and one data record with an empty data block.
const MIN_LEN: usize = field::MESSAGE + record::HEADER_LEN;

/// A view of MDT telegram bytes: `ADR` then the message field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MdtPacket<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> MdtPacket<T> {
    /// Wraps a buffer without checking its length. Getters on a short buffer read 0 or empty
    /// slices and setters do nothing; nothing panics.
    pub const fn new_unchecked(buffer: T) -> MdtPacket<T> {
        MdtPacket { buffer }
    }

    /// Wraps a buffer of at least 5 bytes (ADR and one data record).
    pub fn new_checked(buffer: T) -> Result<MdtPacket<T>, TelegramError> {
        let packet = MdtPacket::new_unchecked(buffer);
        packet.check_len()?;
        Ok(packet)
    }

    /// Checks that the buffer holds ADR and at least one record header (sercos-telegrams.md,
    /// MDT: the message field holds one data record or one per drive).
    pub fn check_len(&self) -> Result<(), TelegramError> {
        TelegramError::check_at_least("MDT", MIN_LEN, self.buffer.as_ref().len())
    }

    /// The wrapped buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// The ADR byte: a drive (phases 0–2) or broadcast (phases 3–4).
    pub fn address(&self) -> Address {
        Address::from(field::read_u8(self.buffer.as_ref(), field::ADR))
    }

    /// The message field: every byte after ADR.
    pub fn message_field(&self) -> &[u8] {
        self.buffer
            .as_ref()
            .get(field::MESSAGE..)
            .unwrap_or_default()
    }

    /// The single data record of an MDT addressed to one drive: the whole message field.
    pub fn record(&self) -> Result<DataRecord<&[u8]>, TelegramError> {
        DataRecord::new_checked(self.message_field())
    }

    /// The data record at `offset` (counted from the first byte after ADR) whose data block is
    /// `data_block_len` bytes long, or [`TelegramError::RecordOutOfBounds`] if it does not fit.
    pub fn record_at(
        &self,
        offset: usize,
        data_block_len: usize,
    ) -> Result<DataRecord<&[u8]>, TelegramError> {
        // sercos-telegrams.md, MDT: "the Master informs the Slave of the byte offset into the
        // MDT at which the Data Record resides for that Slave".
        data_record::locate(self.message_field(), offset, data_block_len)
            .map(DataRecord::new_unchecked)
    }
}

impl<'a, T: AsRef<[u8]> + ?Sized> MdtPacket<&'a T> {
    /// The message field, borrowed for the buffer's lifetime.
    pub fn message_field_ref(&self) -> &'a [u8] {
        self.buffer
            .as_ref()
            .get(field::MESSAGE..)
            .unwrap_or_default()
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> MdtPacket<T> {
    /// Sets the ADR byte.
    pub fn set_address(&mut self, address: Address) {
        field::write_u8(self.buffer.as_mut(), field::ADR, address.to_byte());
    }

    /// The message field, writable.
    pub fn message_field_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(field::MESSAGE..)
            .unwrap_or_default()
    }

    /// The single data record, writable.
    pub fn record_mut(&mut self) -> Result<DataRecord<&mut [u8]>, TelegramError> {
        DataRecord::new_checked(self.message_field_mut())
    }

    /// The data record at `offset` (from the first byte after ADR), writable.
    pub fn record_at_mut(
        &mut self,
        offset: usize,
        data_block_len: usize,
    ) -> Result<DataRecord<&mut [u8]>, TelegramError> {
        data_record::locate_mut(self.message_field_mut(), offset, data_block_len)
            .map(DataRecord::new_unchecked)
    }

    /// Writes `record` at `offset` (from the first byte after ADR) of a broadcast MDT.
    pub fn set_record_at(
        &mut self,
        offset: usize,
        record: &MdtRecordRepr<'_>,
    ) -> Result<(), TelegramError> {
        let mut view = self.record_at_mut(offset, record.data_block.len())?;
        record.emit(&mut view)
    }
}

/// An MDT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MdtRepr<'a> {
    /// Phases 0–2: addressed to one drive, one data record (sercos-telegrams.md, MDT: "the
    /// MDT Message Field contains only one Data Record").
    Single {
        /// The addressed drive.
        address: DriveAddress,
        /// Its data record (the data block is empty in phase 2).
        record: MdtRecordRepr<'a>,
    },
    /// Phases 3–4: ADR 255, one record per drive at offsets only the configuration knows;
    /// the message field is kept whole. Read records with [`MdtRepr::record_at`].
    Broadcast {
        /// Every byte after ADR.
        message_field: &'a [u8],
    },
}

impl<'a> MdtRepr<'a> {
    /// Parses an MDT view. ADR 1–254 gives [`MdtRepr::Single`] (the whole message field is the
    /// record), ADR 255 gives [`MdtRepr::Broadcast`], ADR 0 is an error (no station to
    /// address; sercos-telegrams.md, ADR table: MDT 1–254 or 255).
    pub fn parse<T: AsRef<[u8]> + ?Sized>(
        packet: &MdtPacket<&'a T>,
    ) -> Result<MdtRepr<'a>, TelegramError> {
        packet.check_len()?;
        let message_field = packet.message_field_ref();
        match packet.address() {
            Address::Drive(address) => Ok(MdtRepr::Single {
                address,
                record: MdtRecordRepr::parse(&DataRecord::new_unchecked(message_field))?,
            }),
            Address::Broadcast => Ok(MdtRepr::Broadcast { message_field }),
            address @ Address::NoStation => Err(TelegramError::BadAddress {
                kind: TelegramKind::Mdt,
                address,
            }),
        }
    }

    /// The ADR byte this MDT carries.
    pub fn address(&self) -> Address {
        match self {
            MdtRepr::Single { address, .. } => Address::Drive(*address),
            MdtRepr::Broadcast { .. } => Address::Broadcast,
        }
    }

    /// The record at `offset` (from the first byte after ADR) with a data block of
    /// `data_block_len` bytes. For [`MdtRepr::Single`] only offset 0 with the record's own
    /// length fits.
    pub fn record_at(
        &self,
        offset: usize,
        data_block_len: usize,
    ) -> Result<MdtRecordRepr<'a>, TelegramError> {
        match self {
            MdtRepr::Broadcast { message_field } => {
                let bytes = data_record::locate(message_field, offset, data_block_len)?;
                MdtRecordRepr::parse(&DataRecord::new_unchecked(bytes))
            }
            MdtRepr::Single { record, .. } => {
                let len = record::HEADER_LEN.saturating_add(data_block_len);
                if offset == 0 && data_block_len == record.data_block.len() {
                    Ok(*record)
                } else {
                    Err(TelegramError::RecordOutOfBounds {
                        offset,
                        len,
                        available: record.buffer_len(),
                    })
                }
            }
        }
    }

    /// The telegram length in bytes (ADR and message field).
    pub fn buffer_len(&self) -> usize {
        field::MESSAGE
            + match self {
                MdtRepr::Single { record, .. } => record.buffer_len(),
                MdtRepr::Broadcast { message_field } => message_field.len(),
            }
    }

    /// Writes the MDT into a view of exactly [`buffer_len`](Self::buffer_len) bytes.
    pub fn emit<T: AsRef<[u8]> + AsMut<[u8]>>(
        &self,
        packet: &mut MdtPacket<T>,
    ) -> Result<(), TelegramError> {
        let got = packet.buffer.as_ref().len();
        if got != self.buffer_len() {
            return Err(TelegramError::BufferLength {
                what: "MDT",
                needed: self.buffer_len(),
                got,
            });
        }
        packet.set_address(self.address());
        match self {
            MdtRepr::Single { record, .. } => {
                let mut view = DataRecord::new_unchecked(packet.message_field_mut());
                record.emit(&mut view)
            }
            MdtRepr::Broadcast { message_field } => {
                for (to, from) in packet.message_field_mut().iter_mut().zip(*message_field) {
                    *to = *from;
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::telegram::ControlWord;

    #[test]
    fn broadcast_records_are_found_by_offset_after_adr() {
        // sercos-telegrams.md, MDT: one data record per drive, located by byte offset.
        let mut bytes = [0u8; 1 + 2 * 8];
        let mut packet = MdtPacket::new_checked(&mut bytes[..]).expect("long enough");
        packet.set_address(Address::Broadcast);
        let first = MdtRecordRepr {
            word: ControlWord::from_raw(0xE000),
            service_info: 0x0001,
            data_block: &[1, 2, 3, 4],
        };
        let second = MdtRecordRepr {
            word: ControlWord::from_raw(0x0008),
            service_info: 0x0002,
            data_block: &[5, 6, 7, 8],
        };
        packet.set_record_at(0, &first).expect("fits");
        packet.set_record_at(8, &second).expect("fits");
        assert_eq!(bytes[1..3], [0x00, 0xE0]);
        assert_eq!(bytes[9..11], [0x08, 0x00]);

        let packet = MdtPacket::new_checked(&bytes[..]).expect("long enough");
        let repr = MdtRepr::parse(&packet).expect("valid");
        assert_eq!(repr.record_at(0, 4), Ok(first));
        assert_eq!(repr.record_at(8, 4), Ok(second));
        assert!(matches!(
            repr.record_at(9, 4),
            Err(TelegramError::RecordOutOfBounds { .. })
        ));
    }
}
