//! The standard IDNs sercon knows: name, unit, attribute, typical limits and default.
//!
//! Sources: sercos-facts.md, "Timing parameters" and "IDNs"; the IDNs the TC2000R captures
//! touch (`../shared/captures/README.md`); the telegram-type table of S-0-0015 (Beckhoff
//! AX2000 and AMK manuals). Units, limits, defaults and the manufacturer IDNs (P-0-xxxx) are
//! readings chosen for the emulated drive (docs/spec-notes.md, "IDN catalog").
//!
//! Used by the capture transcript ("S-0-0002 communication cycle time = 2000 µs") and by the
//! emulated drive as its defaults.

use crate::attribute::{Attribute, DataLength, DisplayFormat};
use crate::idn::Idn;

#[cfg(feature = "alloc")]
use crate::attribute::{AttributeError, Value};
#[cfg(feature = "alloc")]
use alloc::{format, string::String};

/// The default operation data of a catalogue entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CatalogDefault {
    /// A single number (fixed-length data).
    Number(i64),
    /// Text (a variable list of bytes).
    Text(&'static str),
    /// A list of IDNs (a variable list of words), by raw value.
    IdnList(&'static [u16]),
}

/// One standard IDN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IdnInfo {
    /// The IDN.
    pub idn: Idn,
    /// Element 2, the name, in lower case as it reads in a sentence.
    pub name: &'static str,
    /// Element 4, the unit ("" for none).
    pub unit: &'static str,
    /// Element 3, the attribute.
    pub attribute: Attribute,
    /// Element 5, the typical minimum input value (fixed-length numbers only).
    pub min: Option<i64>,
    /// Element 6, the typical maximum input value (fixed-length numbers only).
    pub max: Option<i64>,
    /// Maximum length in bytes for variable-length data; 0 for fixed-length data.
    pub max_len: u16,
    /// The default operation data.
    pub default: CatalogDefault,
}

impl IdnInfo {
    /// Formats operation data words of this IDN for people, with the unit:
    /// `2000 µs`, `[S-0-0011, S-0-0051]`.
    #[cfg(feature = "alloc")]
    pub fn display_words(&self, words: &[u16]) -> Result<String, AttributeError> {
        let value: Value = self.attribute.decode(words)?;
        let shown = self.attribute.display(&value);
        Ok(if self.unit.is_empty() {
            format!("{shown}")
        } else {
            format!("{shown} {}", self.unit)
        })
    }
}

// Write protection (sercos-facts.md, attribute bits 30–28) as used in the table below.
const RW: (bool, bool, bool) = (false, false, false);
/// Configuration written in phase 2, fixed from phase 3 on.
const CP2: (bool, bool, bool) = (false, true, true);
/// Written in phases 2 and 3, fixed in phase 4 (operation modes).
const CP23: (bool, bool, bool) = (false, false, true);
/// Read only in every phase.
const RO: (bool, bool, bool) = (true, true, true);

const fn attr(
    length: DataLength,
    format: DisplayFormat,
    places: u8,
    protection: (bool, bool, bool),
) -> Attribute {
    Attribute::new(length, format)
        .with_decimal_places(places)
        .with_write_protection(protection.0, protection.1, protection.2)
}

/// A procedure command: 2-byte binary, bit 19 set (sercos-facts.md, attribute bit 19).
const fn command() -> Attribute {
    Attribute::new(DataLength::TwoBytes, DisplayFormat::Binary).with_procedure_command(true)
}

const fn idn(raw: u16) -> Idn {
    Idn::from_raw(raw)
}

const P: u16 = 0x8000;

#[allow(clippy::too_many_arguments)]
const fn entry(
    raw: u16,
    name: &'static str,
    unit: &'static str,
    attribute: Attribute,
    min: Option<i64>,
    max: Option<i64>,
    max_len: u16,
    default: CatalogDefault,
) -> IdnInfo {
    IdnInfo {
        idn: idn(raw),
        name,
        unit,
        attribute,
        min,
        max,
        max_len,
        default,
    }
}

const fn time(
    raw: u16,
    name: &'static str,
    protection: (bool, bool, bool),
    default: i64,
) -> IdnInfo {
    entry(
        raw,
        name,
        "µs",
        attr(
            DataLength::TwoBytes,
            DisplayFormat::UnsignedDecimal,
            0,
            protection,
        ),
        Some(0),
        Some(65_000),
        0,
        CatalogDefault::Number(default),
    )
}

const fn word(
    raw: u16,
    name: &'static str,
    format: DisplayFormat,
    protection: (bool, bool, bool),
    min: Option<i64>,
    max: Option<i64>,
    default: i64,
) -> IdnInfo {
    entry(
        raw,
        name,
        "",
        attr(DataLength::TwoBytes, format, 0, protection),
        min,
        max,
        0,
        CatalogDefault::Number(default),
    )
}

const fn idn_list(
    raw: u16,
    name: &'static str,
    protection: (bool, bool, bool),
    max_len: u16,
    default: &'static [u16],
) -> IdnInfo {
    entry(
        raw,
        name,
        "",
        attr(DataLength::VariableWords, DisplayFormat::Idn, 0, protection),
        None,
        None,
        max_len,
        CatalogDefault::IdnList(default),
    )
}

const fn signed32(
    raw: u16,
    name: &'static str,
    unit: &'static str,
    places: u8,
    protection: (bool, bool, bool),
) -> IdnInfo {
    entry(
        raw,
        name,
        unit,
        attr(
            DataLength::FourBytes,
            DisplayFormat::SignedDecimal,
            places,
            protection,
        ),
        Some(i32::MIN as i64),
        Some(i32::MAX as i64),
        0,
        CatalogDefault::Number(0),
    )
}

const fn procedure(raw: u16, name: &'static str) -> IdnInfo {
    entry(
        raw,
        name,
        "",
        command(),
        Some(0),
        Some(3),
        0,
        CatalogDefault::Number(0),
    )
}

/// Operation modes (S-0-0032…S-0-0035): the value 2 is velocity control, the mode the
/// captures' master configures with S-0-0036 in the MDT (docs/spec-notes.md, "IDN catalog").
const fn mode(raw: u16, name: &'static str, default: i64) -> IdnInfo {
    word(
        raw,
        name,
        DisplayFormat::Binary,
        CP23,
        Some(0),
        Some(0xFFFF),
        default,
    )
}

/// Every IDN the catalogue knows, sorted by raw IDN value.
pub static CATALOG: &[IdnInfo] = &[
    // sercos-facts.md, "Timing parameters".
    time(1, "NC cycle time tNcyc", CP2, 2000),
    time(2, "communication cycle time tScyc", CP2, 2000),
    time(3, "minimum AT transmit starting time t1min", RO, 40),
    time(4, "transmit/receive transition time tATMT", RO, 20),
    time(5, "minimum feedback acquisition time t5", RO, 100),
    time(6, "AT transmission starting time t1", CP2, 0),
    time(7, "feedback acquisition capture point t4", CP2, 0),
    time(8, "command value valid time t3", CP2, 0),
    word(
        9,
        "beginning address in the MDT",
        DisplayFormat::UnsignedDecimal,
        CP2,
        Some(1),
        Some(65_531),
        1,
    ),
    entry(
        10,
        "length of the MDT",
        "bytes",
        attr(DataLength::TwoBytes, DisplayFormat::UnsignedDecimal, 0, CP2),
        Some(0),
        Some(65_534),
        0,
        CatalogDefault::Number(0),
    ),
    // Diagnostics: classes 1–3 and the interface status.
    word(
        11,
        "class 1 diagnostic",
        DisplayFormat::Binary,
        RO,
        None,
        None,
        0,
    ),
    word(
        12,
        "class 2 diagnostic",
        DisplayFormat::Binary,
        RO,
        None,
        None,
        0,
    ),
    word(
        13,
        "class 3 diagnostic",
        DisplayFormat::Binary,
        RO,
        None,
        None,
        0,
    ),
    word(
        14,
        "interface status",
        DisplayFormat::Binary,
        RO,
        None,
        None,
        0,
    ),
    // Telegram configuration (sercos-facts.md, S-0-0015, S-0-0016, S-0-0024).
    word(
        15,
        "telegram type",
        DisplayFormat::Binary,
        CP2,
        Some(0),
        Some(7),
        0,
    ),
    idn_list(16, "configuration list of the AT", CP2, 32, &[]),
    idn_list(17, "IDN list of all operation data", RO, 512, &[]),
    idn_list(24, "configuration list of the MDT", CP2, 32, &[]),
    mode(32, "primary operation mode", 2),
    mode(33, "secondary operation mode 1", 2),
    mode(34, "secondary operation mode 2", 3),
    mode(35, "secondary operation mode 3", 1),
    signed32(36, "velocity command value", "rpm", 4, RW),
    signed32(40, "velocity feedback value 1", "rpm", 4, RO),
    signed32(47, "position command value", "deg", 4, RW),
    signed32(51, "position feedback value 1", "deg", 4, RO),
    entry(
        80,
        "torque command value",
        "%",
        attr(DataLength::TwoBytes, DisplayFormat::SignedDecimal, 1, RW),
        Some(-5000),
        Some(5000),
        0,
        CatalogDefault::Number(0),
    ),
    time(88, "receive-to-receive recovery time tMTSY", RO, 20),
    time(89, "MDT transmission starting time t2", CP2, 0),
    time(90, "command value transmit time tMTSG", RO, 20),
    entry(
        95,
        "diagnostic message",
        "",
        attr(DataLength::VariableBytes, DisplayFormat::Text, 0, RO),
        None,
        None,
        64,
        CatalogDefault::Text(""),
    ),
    word(
        96,
        "slave arrangement",
        DisplayFormat::Hexadecimal,
        RO,
        None,
        None,
        0,
    ),
    procedure(99, "reset class 1 diagnostic"),
    procedure(127, "communication phase 3 transition check"),
    procedure(128, "communication phase 4 transition check"),
    word(
        134,
        "master control word",
        DisplayFormat::Binary,
        RO,
        None,
        None,
        0,
    ),
    word(
        135,
        "drive status word",
        DisplayFormat::Binary,
        RO,
        None,
        None,
        0,
    ),
    idn_list(
        187,
        "IDN list of configurable data in the AT",
        RO,
        32,
        &[11, 12, 13, 40, 51, 135, P | 19],
    ),
    idn_list(
        188,
        "IDN list of configurable data in the MDT",
        RO,
        32,
        &[36, 47, 80, 134],
    ),
    // Manufacturer IDNs of the emulated drive (docs/spec-notes.md, "IDN catalog").
    entry(
        P | 1,
        "velocity loop time constant",
        "ms",
        attr(
            DataLength::TwoBytes,
            DisplayFormat::UnsignedDecimal,
            1,
            CP23,
        ),
        Some(1),
        Some(10_000),
        0,
        CatalogDefault::Number(50),
    ),
    entry(
        P | 2,
        "bit rate",
        "Mbit/s",
        attr(DataLength::TwoBytes, DisplayFormat::UnsignedDecimal, 0, CP2),
        Some(2),
        Some(16),
        0,
        CatalogDefault::Number(2),
    ),
    word(
        P | 3,
        "simulated fault",
        DisplayFormat::Binary,
        RW,
        Some(0),
        Some(1),
        0,
    ),
    entry(
        P | 19,
        "torque feedback value",
        "%",
        attr(DataLength::TwoBytes, DisplayFormat::SignedDecimal, 1, RO),
        Some(-5000),
        Some(5000),
        0,
        CatalogDefault::Number(0),
    ),
];

/// The catalogue entry of `idn`, if the catalogue knows it.
pub fn lookup(idn: Idn) -> Option<&'static IdnInfo> {
    CATALOG
        .binary_search_by_key(&idn.raw(), |info| info.idn.raw())
        .ok()
        .and_then(|index| CATALOG.get(index))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorted_and_unique() {
        assert!(CATALOG.windows(2).all(|pair| match pair {
            [a, b] => a.idn.raw() < b.idn.raw(),
            _ => true,
        }));
    }

    #[test]
    fn every_idn_the_captures_touch() {
        // captures/README.md, phase 2: the IDNs the master reads and writes.
        for raw in [
            1,
            2,
            3,
            4,
            5,
            6,
            7,
            8,
            9,
            10,
            11,
            15,
            16,
            24,
            36,
            51,
            88,
            89,
            90,
            96,
            99,
            127,
            128,
            P | 19,
        ] {
            assert!(
                lookup(Idn::from_raw(raw)).is_some(),
                "{}",
                Idn::from_raw(raw)
            );
        }
        assert!(lookup(Idn::from_raw(4095)).is_none());
    }

    #[test]
    fn procedure_commands_have_bit_19() {
        // sercos-facts.md: S-0-0099, S-0-0127, S-0-0128 are procedure commands.
        for raw in [99, 127, 128] {
            let info = lookup(Idn::from_raw(raw));
            assert!(info.is_some_and(|i| i.attribute.is_procedure_command()));
        }
        assert!(lookup(Idn::from_raw(2)).is_some_and(|i| !i.attribute.is_procedure_command()));
    }

    #[test]
    fn defaults_fit_their_attribute() {
        for info in CATALOG {
            match info.default {
                CatalogDefault::Number(n) => {
                    assert!(info.attribute.fixed_words().is_some(), "{}", info.idn);
                    assert!(info.min.is_none_or(|min| n >= min), "{}", info.idn);
                    assert!(info.max.is_none_or(|max| n <= max), "{}", info.idn);
                }
                CatalogDefault::Text(text) => {
                    assert!(text.len() <= usize::from(info.max_len), "{}", info.idn)
                }
                CatalogDefault::IdnList(list) => {
                    assert!(list.len() * 2 <= usize::from(info.max_len), "{}", info.idn)
                }
            }
        }
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn transcript_line() {
        let info = lookup(Idn::COMMUNICATION_CYCLE_TIME);
        let shown = info.map(|i| (i.name, i.display_words(&[2000])));
        assert_eq!(
            shown,
            Some((
                "communication cycle time tScyc",
                Ok(String::from("2000 µs"))
            ))
        );
    }
}
