//! The amplifier telegram (AT): ADR = the sending drive, one data record whose first word is
//! the status word (sercos-telegrams.md, Amplifier Telegram).

use crate::address::{Address, DriveAddress};

use super::data_record::{AtRecordRepr, DataRecord};
use super::field::{self, record};
use super::{StatusWord, TelegramError, TelegramKind};

/// The smallest AT: ADR and a data record with an empty data block (phase 2).
const MIN_LEN: usize = field::MESSAGE + record::HEADER_LEN;

/// A view of AT telegram bytes: `ADR status service_info data_block`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AtPacket<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> AtPacket<T> {
    /// Wraps a buffer without checking its length. Getters on a short buffer read 0 or empty
    /// slices and setters do nothing; nothing panics.
    pub const fn new_unchecked(buffer: T) -> AtPacket<T> {
        AtPacket { buffer }
    }

    /// Wraps a buffer of at least 5 bytes (ADR, status word, service info).
    pub fn new_checked(buffer: T) -> Result<AtPacket<T>, TelegramError> {
        let packet = AtPacket::new_unchecked(buffer);
        packet.check_len()?;
        Ok(packet)
    }

    /// Checks that the buffer holds ADR and a record header (sercos-telegrams.md, AT: "The
    /// AT Message Field contains one Data Record").
    pub fn check_len(&self) -> Result<(), TelegramError> {
        TelegramError::check_at_least("AT", MIN_LEN, self.buffer.as_ref().len())
    }

    /// The wrapped buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// The ADR byte: the sending drive (sercos-telegrams.md, ADR: "In a telegram from a Slave
    /// (drive), the address specifies the sourcing drive").
    pub fn address(&self) -> Address {
        Address::from(field::read_u8(self.buffer.as_ref(), field::ADR))
    }

    /// The data record (every byte after ADR).
    pub fn record(&self) -> DataRecord<&[u8]> {
        DataRecord::new_unchecked(
            self.buffer
                .as_ref()
                .get(field::MESSAGE..)
                .unwrap_or_default(),
        )
    }

    /// The status word.
    pub fn status_word(&self) -> StatusWord {
        self.record().status_word()
    }

    /// The service info word.
    pub fn service_info(&self) -> u16 {
        self.record().service_info()
    }

    /// The data block (operation data), possibly empty.
    pub fn data_block(&self) -> &[u8] {
        self.buffer
            .as_ref()
            .get(field::MESSAGE + record::DATA_BLOCK..)
            .unwrap_or_default()
    }
}

impl<'a, T: AsRef<[u8]> + ?Sized> AtPacket<&'a T> {
    /// The data record, borrowed for the buffer's lifetime.
    pub fn record_ref(&self) -> DataRecord<&'a [u8]> {
        DataRecord::new_unchecked(
            self.buffer
                .as_ref()
                .get(field::MESSAGE..)
                .unwrap_or_default(),
        )
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> AtPacket<T> {
    /// Sets the ADR byte.
    pub fn set_address(&mut self, address: Address) {
        field::write_u8(self.buffer.as_mut(), field::ADR, address.to_byte());
    }

    /// The data record, writable.
    pub fn record_mut(&mut self) -> DataRecord<&mut [u8]> {
        DataRecord::new_unchecked(
            self.buffer
                .as_mut()
                .get_mut(field::MESSAGE..)
                .unwrap_or_default(),
        )
    }

    /// Sets the status word.
    pub fn set_status_word(&mut self, word: StatusWord) {
        self.record_mut().set_status_word(word);
    }

    /// Sets the service info word.
    pub fn set_service_info(&mut self, info: u16) {
        self.record_mut().set_service_info(info);
    }
}

/// An AT: the sending drive and its data record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AtRepr<'a> {
    /// The sending drive (1–254).
    pub address: DriveAddress,
    /// Status word, service info, data block.
    pub record: AtRecordRepr<'a>,
}

impl<'a> AtRepr<'a> {
    /// Parses an AT view. ADR must be a drive address: an AT names the drive that sends it
    /// (sercos-telegrams.md, ADR table: AT 1–254), so 0 and 255 are errors.
    pub fn parse<T: AsRef<[u8]> + ?Sized>(
        packet: &AtPacket<&'a T>,
    ) -> Result<AtRepr<'a>, TelegramError> {
        packet.check_len()?;
        let address = match packet.address() {
            Address::Drive(drive) => drive,
            address => {
                return Err(TelegramError::BadAddress {
                    kind: TelegramKind::At,
                    address,
                });
            }
        };
        Ok(AtRepr {
            address,
            record: AtRecordRepr::parse(&packet.record_ref())?,
        })
    }

    /// The telegram length in bytes (ADR and record).
    pub fn buffer_len(&self) -> usize {
        field::MESSAGE + self.record.buffer_len()
    }

    /// Writes the AT into a view of exactly [`buffer_len`](Self::buffer_len) bytes.
    pub fn emit<T: AsRef<[u8]> + AsMut<[u8]>>(
        &self,
        packet: &mut AtPacket<T>,
    ) -> Result<(), TelegramError> {
        let got = packet.buffer.as_ref().len();
        if got != self.buffer_len() {
            return Err(TelegramError::BufferLength {
                what: "AT",
                needed: self.buffer_len(),
                got,
            });
        }
        packet.set_address(Address::Drive(self.address));
        self.record.emit(&mut packet.record_mut())
    }
}
