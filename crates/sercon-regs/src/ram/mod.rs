//! The dual-port RAM: its fixed words and the structures of 410B §4.2.
//!
//! All pointers are word addresses into the RAM (ERRATA "word addresses"). Every
//! structure has an owned representation with public fields, decoded from and encoded
//! to its words; bits the datasheet marks "(Not used)" are kept in a `reserved` field so
//! that decode followed by encode gives back the same words.

pub mod container;
pub mod header;
pub mod service;
pub mod service_rules;

/// Word 0: COMPT0, start of transmission block 0 (410B §4.2).
pub const COMPT0: u16 = 0;
/// Word 1: COMPT1, start of transmission block 1 (410B §4.2).
pub const COMPT1: u16 = 1;
/// Word 2: SCPT0, address of service container 0 (410B §4.2); SCPTn is word 2 + n.
pub const SCPT0: u16 = 2;
/// Word 3: SCPT1 (410B §4.2).
pub const SCPT1: u16 = 3;
/// Word 4: SCPT2 (410B §4.2).
pub const SCPT2: u16 = 4;
/// Word 5: SCPT3 (410B §4.2).
pub const SCPT3: u16 = 5;
/// Word 6: SCPT4 (410B §4.2).
pub const SCPT4: u16 = 6;
/// Word 7: SCPT5 (410B §4.2).
pub const SCPT5: u16 = 7;
/// Word 8: SCPT6 (410B §4.2).
pub const SCPT6: u16 = 8;
/// Word 9: SCPT7 (410B §4.2).
pub const SCPT7: u16 = 9;
/// Word 10: NMSTERR, error counter MST (410B §4.2).
pub const NMSTERR: u16 = 10;
/// Number of words with a fixed meaning (410B §4.2: "the first eleven words"); the
/// rest of the RAM can be divided as required.
pub const FIXED_WORDS: u16 = 11;

/// Word address of COMPTn, the start of transmission block `block` (0 or 1).
#[doc(alias = "COMPT")]
pub const fn compt(block: u8) -> Option<u16> {
    match block {
        0 => Some(COMPT0),
        1 => Some(COMPT1),
        _ => None,
    }
}

/// Word address of SCPTn, the pointer to service container `n` (0–7).
#[doc(alias = "SCPT")]
pub const fn scpt(n: u8) -> Option<u16> {
    if n < 8 { Some(SCPT0 + n as u16) } else { None }
}
