//! Byte offsets of the telegram fields, and the little-endian word access every view uses.
//!
//! Offsets are into the telegram bytes: the ADR byte followed by the message field, as they
//! are between the flags, without FCS and flags (ERRATA.md, Telegrams: "frame").

/// A byte range.
pub(crate) type Field = core::ops::Range<usize>;

/// sercos-telegrams.md, all telegrams: the ADR byte follows the BOF flag.
pub(crate) const ADR: usize = 0;
/// sercos-telegrams.md: the message field follows ADR.
pub(crate) const MESSAGE: usize = 1;

/// sercos-telegrams.md, MST: "The Message Field for the MST consists of one 8-bit word."
pub(crate) const MST_PHASE: usize = 1;
/// ADR and the phase byte.
pub(crate) const MST_LEN: usize = 2;

/// Offsets inside a data record (relative to the record's first byte).
pub(crate) mod record {
    use super::Field;

    /// sercos-telegrams.md, Data Record: "a 16-bit Control/Status word".
    pub(crate) const WORD: Field = 0..2;
    /// sercos-telegrams.md, Data Record: "a 16-bit Service Channel" (service info).
    pub(crate) const SERVICE_INFO: Field = 2..4;
    /// sercos-telegrams.md, Data Record: "and a Data Block"; it runs to the record's end.
    pub(crate) const DATA_BLOCK: usize = 4;
    /// A record with an empty data block (phase 2, sercos-telegrams.md, Data Record).
    pub(crate) const HEADER_LEN: usize = DATA_BLOCK;
}

/// Reads the little-endian word at `field`; 0 if the buffer is too short (never panics).
///
/// ERRATA.md, Telegrams: "16-bit words go low byte first".
pub(crate) fn read_u16(buffer: &[u8], field: Field) -> u16 {
    match buffer.get(field) {
        Some(&[low, high]) => u16::from_le_bytes([low, high]),
        _ => 0,
    }
}

/// Writes `value` little endian at `field`; does nothing if the buffer is too short.
pub(crate) fn write_u16(buffer: &mut [u8], field: Field, value: u16) {
    if let Some(bytes) = buffer.get_mut(field) {
        if bytes.len() == 2 {
            bytes.copy_from_slice(&value.to_le_bytes());
        }
    }
}

/// Reads the byte at `offset`; 0 if the buffer is too short.
pub(crate) fn read_u8(buffer: &[u8], offset: usize) -> u8 {
    buffer.get(offset).copied().unwrap_or(0)
}

/// Writes the byte at `offset`; does nothing if the buffer is too short.
pub(crate) fn write_u8(buffer: &mut [u8], offset: usize, value: u8) {
    if let Some(byte) = buffer.get_mut(offset) {
        *byte = value;
    }
}
