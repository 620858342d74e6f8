//! Frame check sequence (ERRATA, Telegrams: ISO/IEC 3309 FCS, CRC-16/IBM-SDLC).

use crc::{CRC_16_IBM_SDLC, Crc, Table};

/// Bytes of FCS after the telegram bytes.
pub const FCS_LEN: usize = 2;

/// ERRATA, Telegrams: CRC-16 poly 1021H reflected, init FFFFH, xorout FFFFH.
/// A 16-entry slice table keeps the check fast enough for a gigabit decoder.
static CRC: Crc<u16, Table<16>> = Crc::<u16, Table<16>>::new(&CRC_16_IBM_SDLC);

/// The FCS over telegram bytes (ADR and data). It is sent low byte first
/// (ERRATA, Telegrams).
pub fn fcs(telegram: &[u8]) -> u16 {
    CRC.checksum(telegram)
}
