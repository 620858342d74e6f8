//! The data record: control or status word, service info, data block.
//!
//! sercos-telegrams.md, Data Record: "a Data Record consists of a 16-bit Control/Status word,
//! a 16-bit Service Channel, and a Data Block of 16-bit words." The data block may be empty
//! (phase 2) and its length is configured by the master in phase 2.

use super::field::{self, record};
use super::{ControlWord, StatusWord, TelegramError};

/// A view of one data record; the record is the whole buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataRecord<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> DataRecord<T> {
    /// Wraps a buffer without checking its length. Getters on a short buffer read 0 or an
    /// empty block and setters do nothing; nothing panics.
    pub const fn new_unchecked(buffer: T) -> DataRecord<T> {
        DataRecord { buffer }
    }

    /// Wraps a buffer of at least 4 bytes (word and service info); the rest is the data block.
    pub fn new_checked(buffer: T) -> Result<DataRecord<T>, TelegramError> {
        let record = DataRecord::new_unchecked(buffer);
        record.check_len()?;
        Ok(record)
    }

    /// Checks that the buffer holds the word and the service info.
    pub fn check_len(&self) -> Result<(), TelegramError> {
        TelegramError::check_at_least(
            "data record",
            record::HEADER_LEN,
            self.buffer.as_ref().len(),
        )
    }

    /// The wrapped buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// The record length in bytes (4 + data block).
    pub fn len(&self) -> usize {
        self.buffer.as_ref().len()
    }

    /// Whether the buffer is empty (then it is not a valid record).
    pub fn is_empty(&self) -> bool {
        self.buffer.as_ref().is_empty()
    }

    /// The first word, raw: the control word in an MDT, the status word in an AT.
    pub fn word(&self) -> u16 {
        field::read_u16(self.buffer.as_ref(), record::WORD)
    }

    /// The first word read as an MDT control word.
    pub fn control_word(&self) -> ControlWord {
        ControlWord::from_raw(self.word())
    }

    /// The first word read as an AT status word.
    pub fn status_word(&self) -> StatusWord {
        StatusWord::from_raw(self.word())
    }

    /// The service info (service channel) word.
    #[doc(alias = "service_channel")]
    pub fn service_info(&self) -> u16 {
        field::read_u16(self.buffer.as_ref(), record::SERVICE_INFO)
    }

    /// The data block (bytes after the service info), possibly empty.
    pub fn data_block(&self) -> &[u8] {
        self.buffer
            .as_ref()
            .get(record::DATA_BLOCK..)
            .unwrap_or_default()
    }
}

impl<'a, T: AsRef<[u8]> + ?Sized> DataRecord<&'a T> {
    /// The data block, borrowed for the buffer's lifetime.
    pub fn data_block_ref(&self) -> &'a [u8] {
        self.buffer
            .as_ref()
            .get(record::DATA_BLOCK..)
            .unwrap_or_default()
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> DataRecord<T> {
    /// Sets the first word, raw.
    pub fn set_word(&mut self, word: u16) {
        field::write_u16(self.buffer.as_mut(), record::WORD, word);
    }

    /// Sets the first word to an MDT control word.
    pub fn set_control_word(&mut self, word: ControlWord) {
        self.set_word(word.raw());
    }

    /// Sets the first word to an AT status word.
    pub fn set_status_word(&mut self, word: StatusWord) {
        self.set_word(word.raw());
    }

    /// Sets the service info word.
    pub fn set_service_info(&mut self, info: u16) {
        field::write_u16(self.buffer.as_mut(), record::SERVICE_INFO, info);
    }

    /// The data block, writable.
    pub fn data_block_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(record::DATA_BLOCK..)
            .unwrap_or_default()
    }
}

/// Finds the record at `offset` bytes into `message` with a data block of `data_block_len`
/// bytes, as a view over exactly its bytes.
pub(crate) fn locate(
    message: &[u8],
    offset: usize,
    data_block_len: usize,
) -> Result<&[u8], TelegramError> {
    let len = record::HEADER_LEN.saturating_add(data_block_len);
    let out_of_bounds = TelegramError::RecordOutOfBounds {
        offset,
        len,
        available: message.len(),
    };
    let end = offset.checked_add(len).ok_or(out_of_bounds)?;
    message.get(offset..end).ok_or(out_of_bounds)
}

/// The writable twin of [`locate`].
pub(crate) fn locate_mut(
    message: &mut [u8],
    offset: usize,
    data_block_len: usize,
) -> Result<&mut [u8], TelegramError> {
    let len = record::HEADER_LEN.saturating_add(data_block_len);
    let out_of_bounds = TelegramError::RecordOutOfBounds {
        offset,
        len,
        available: message.len(),
    };
    let end = offset.checked_add(len).ok_or(out_of_bounds)?;
    message.get_mut(offset..end).ok_or(out_of_bounds)
}

/// A data record: its first word (`W` is [`ControlWord`] in an MDT, [`StatusWord`] in an AT,
/// or a raw `u16`), the service info, and the data block borrowed from the telegram bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct DataRecordRepr<'a, W = u16> {
    /// The control word (MDT) or status word (AT).
    pub word: W,
    /// The service info word (sercos-telegrams.md: "Contains the non-cyclic data").
    #[doc(alias = "service_channel")]
    pub service_info: u16,
    /// The data block (cyclic data), possibly empty.
    pub data_block: &'a [u8],
}

/// A data record of an MDT.
pub type MdtRecordRepr<'a> = DataRecordRepr<'a, ControlWord>;
/// The data record of an AT.
pub type AtRecordRepr<'a> = DataRecordRepr<'a, StatusWord>;

impl<'a, W: From<u16> + Into<u16> + Copy> DataRecordRepr<'a, W> {
    /// Reads a record view (at least 4 bytes).
    pub fn parse<T: AsRef<[u8]> + ?Sized>(
        record: &DataRecord<&'a T>,
    ) -> Result<DataRecordRepr<'a, W>, TelegramError> {
        record.check_len()?;
        Ok(DataRecordRepr {
            word: W::from(record.word()),
            service_info: record.service_info(),
            data_block: record.data_block_ref(),
        })
    }

    /// The record length in bytes: 4 + data block.
    pub fn buffer_len(&self) -> usize {
        record::HEADER_LEN + self.data_block.len()
    }

    /// Writes the record into a view of exactly [`buffer_len`](Self::buffer_len) bytes.
    pub fn emit<T: AsRef<[u8]> + AsMut<[u8]>>(
        &self,
        record: &mut DataRecord<T>,
    ) -> Result<(), TelegramError> {
        let got = record.len();
        if got != self.buffer_len() {
            return Err(TelegramError::BufferLength {
                what: "data record",
                needed: self.buffer_len(),
                got,
            });
        }
        record.set_word(self.word.into());
        record.set_service_info(self.service_info);
        for (to, from) in record.data_block_mut().iter_mut().zip(self.data_block) {
            *to = *from;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_little_endian() {
        // ERRATA.md, Telegrams: 16-bit words go low byte first.
        let bytes = [0x08, 0xE0, 0x34, 0x12, 0xAA];
        let record = DataRecord::new_checked(&bytes[..]).expect("5 bytes");
        assert_eq!(record.word(), 0xE008);
        assert_eq!(record.service_info(), 0x1234);
        assert_eq!(record.data_block(), &[0xAA]);
    }

    #[test]
    fn locate_rejects_records_past_the_end() {
        let message = [0u8; 16];
        assert!(locate(&message, 8, 4).is_ok());
        assert_eq!(
            locate(&message, 9, 4),
            Err(TelegramError::RecordOutOfBounds {
                offset: 9,
                len: 8,
                available: 16
            })
        );
        assert!(locate(&message, usize::MAX, usize::MAX).is_err());
    }
}
