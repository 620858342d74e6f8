//! Identification numbers (IDNs) and data block elements.
//!
//! sercos-facts.md, IDNs: "16-bit IDN: bit 15 = S (0) / P (1), bits 14–12 = parameter set,
//! bits 11–0 = data block number. Written `S-0-0001`, `P-0-0019`." and "Data block elements:
//! 1 IDN, 2 name, 3 attribute, 4 unit, 5 minimum, 6 maximum, 7 operation data (0 = service
//! channel closed)."

use core::fmt;
use core::str::FromStr;

/// Standard (`S`) or product-specific (`P`) IDN, bit 15.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum IdnKind {
    /// Standard data (`S`), bit 15 = 0.
    #[doc(alias = "S")]
    Standard,
    /// Product-specific data (`P`), bit 15 = 1.
    #[doc(alias = "P")]
    Product,
}

impl IdnKind {
    /// The letter the IDN is written with: `S` or `P`.
    pub const fn letter(self) -> char {
        match self {
            IdnKind::Standard => 'S',
            IdnKind::Product => 'P',
        }
    }
}

/// A 16-bit identification number: `S`/`P`, parameter set 0–7, data block number 0–4095.
///
/// Every `u16` is a valid IDN, so the raw conversions are total and lossless.
/// Written and parsed as `S-0-0001`, `P-3-0123`.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "u16", into = "u16")
)]
pub struct Idn(u16);

/// Why an IDN could not be built from its parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum IdnError {
    /// The parameter set is above 7 (it has three bits, 14–12).
    #[error("parameter set {0} is out of range (0-7)")]
    ParameterSetOutOfRange(u8),
    /// The data block number is above 4095 (it has twelve bits, 11–0).
    #[error("data block number {0} is out of range (0-4095)")]
    NumberOutOfRange(u16),
}

impl Idn {
    // sercos-facts.md, IDNs: bit 15 = S/P, bits 14–12 = parameter set, bits 11–0 = number.
    const KIND_BIT: u16 = 1 << 15;
    const SET_SHIFT: u32 = 12;
    const SET_MASK: u16 = 0b111;
    const NUMBER_MASK: u16 = 0x0FFF;

    /// The highest parameter set, 7.
    pub const MAX_PARAMETER_SET: u8 = 7;
    /// The highest data block number, 4095.
    pub const MAX_NUMBER: u16 = 4095;

    /// S-0-0001, NC cycle time (sercos-facts.md, timing parameters).
    pub const NC_CYCLE_TIME: Idn = Idn(1);
    /// S-0-0002, communication cycle time tScyc.
    pub const COMMUNICATION_CYCLE_TIME: Idn = Idn(2);
    /// S-0-0006, AT transmission starting time t1.
    pub const AT_TRANSMISSION_STARTING_TIME: Idn = Idn(6);
    /// S-0-0009, position of the drive's data record in the MDT.
    pub const MDT_RECORD_POSITION: Idn = Idn(9);
    /// S-0-0010, length of the MDT data.
    pub const MDT_LENGTH: Idn = Idn(10);
    /// S-0-0015, telegram type.
    pub const TELEGRAM_TYPE: Idn = Idn(15);
    /// S-0-0016, configuration list of the AT.
    pub const AT_CONFIGURATION_LIST: Idn = Idn(16);
    /// S-0-0024, configuration list of the MDT.
    pub const MDT_CONFIGURATION_LIST: Idn = Idn(24);
    /// S-0-0089, MDT transmission starting time t2.
    pub const MDT_TRANSMISSION_STARTING_TIME: Idn = Idn(89);
    /// S-0-0127, phase 3 transition check (procedure command).
    pub const PHASE_3_TRANSITION_CHECK: Idn = Idn(127);
    /// S-0-0128, phase 4 transition check (procedure command).
    pub const PHASE_4_TRANSITION_CHECK: Idn = Idn(128);

    /// Builds an IDN from its parts, checking the ranges.
    pub const fn new(kind: IdnKind, parameter_set: u8, number: u16) -> Result<Idn, IdnError> {
        if parameter_set > Self::MAX_PARAMETER_SET {
            return Err(IdnError::ParameterSetOutOfRange(parameter_set));
        }
        if number > Self::MAX_NUMBER {
            return Err(IdnError::NumberOutOfRange(number));
        }
        let kind_bit = match kind {
            IdnKind::Standard => 0,
            IdnKind::Product => Self::KIND_BIT,
        };
        Ok(Idn(kind_bit
            | ((parameter_set as u16) << Self::SET_SHIFT)
            | number))
    }

    /// The IDN from its 16-bit value.
    pub const fn from_raw(raw: u16) -> Idn {
        Idn(raw)
    }

    /// The 16-bit value.
    pub const fn raw(self) -> u16 {
        self.0
    }

    /// `S` (bit 15 = 0) or `P` (bit 15 = 1).
    pub const fn kind(self) -> IdnKind {
        if self.0 & Self::KIND_BIT == 0 {
            IdnKind::Standard
        } else {
            IdnKind::Product
        }
    }

    /// The parameter set, bits 14–12 (0–7).
    pub const fn parameter_set(self) -> u8 {
        ((self.0 >> Self::SET_SHIFT) & Self::SET_MASK) as u8
    }

    /// The data block number, bits 11–0 (0–4095).
    pub const fn number(self) -> u16 {
        self.0 & Self::NUMBER_MASK
    }
}

impl From<u16> for Idn {
    fn from(raw: u16) -> Idn {
        Idn(raw)
    }
}

impl From<Idn> for u16 {
    fn from(idn: Idn) -> u16 {
        idn.0
    }
}

/// Writes `S-0-0001` / `P-3-0123`: letter, set, and the number in four zero-padded digits.
impl fmt::Display for Idn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}-{}-{:04}",
            self.kind().letter(),
            self.parameter_set(),
            self.number()
        )
    }
}

impl fmt::Debug for Idn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Idn({self})")
    }
}

/// Why a string is not an IDN. Positions are byte offsets into the string.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum IdnParseError {
    /// The string is empty.
    #[error("empty IDN (expected e.g. S-0-0001)")]
    Empty,
    /// The first character is not `S` or `P`.
    #[error("bad prefix {found:?}: an IDN starts with S or P")]
    BadPrefix {
        /// The character found instead.
        found: char,
    },
    /// A `-` separator is missing.
    #[error("expected '-' at position {position}")]
    MissingSeparator {
        /// Where the separator should be.
        position: usize,
    },
    /// The parameter set is not a single decimal digit.
    #[error("parameter set at position {position} must be one digit 0-7")]
    BadParameterSet {
        /// Where the parameter set starts.
        position: usize,
    },
    /// The parameter set is the digit 8 or 9.
    #[error("parameter set {0} is out of range (0-7)")]
    ParameterSetOutOfRange(u8),
    /// The data block number has no digits.
    #[error("missing data block number at position {position}")]
    MissingNumber {
        /// Where the number should start.
        position: usize,
    },
    /// The data block number has more than four digits.
    #[error("data block number has more than 4 digits")]
    NumberTooLong,
    /// The data block number is above 4095.
    #[error("data block number {0} is out of range (0-4095)")]
    NumberOutOfRange(u16),
    /// Something follows the data block number.
    #[error("trailing text at position {position}")]
    TrailingText {
        /// Where the extra text starts.
        position: usize,
    },
}

/// Parses `S-0-0001`, `P-3-123`: `S` or `P` (either case), `-`, one digit 0–7, `-`, and 1–4
/// decimal digits ≤ 4095; nothing else (no spaces, no signs).
impl FromStr for Idn {
    type Err = IdnParseError;

    fn from_str(text: &str) -> Result<Idn, IdnParseError> {
        let bytes = text.as_bytes();
        let kind = match text.chars().next() {
            None => return Err(IdnParseError::Empty),
            Some('S' | 's') => IdnKind::Standard,
            Some('P' | 'p') => IdnKind::Product,
            Some(found) => return Err(IdnParseError::BadPrefix { found }),
        };
        expect_separator(bytes, 1)?;
        let parameter_set = match bytes.get(2) {
            Some(digit @ b'0'..=b'9') => digit - b'0',
            _ => return Err(IdnParseError::BadParameterSet { position: 2 }),
        };
        if matches!(bytes.get(3), Some(b'0'..=b'9')) {
            return Err(IdnParseError::BadParameterSet { position: 2 });
        }
        if parameter_set > Idn::MAX_PARAMETER_SET {
            return Err(IdnParseError::ParameterSetOutOfRange(parameter_set));
        }
        expect_separator(bytes, 3)?;
        const NUMBER_START: usize = 4;
        let digits = bytes
            .get(NUMBER_START..)
            .unwrap_or_default()
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count();
        if digits == 0 {
            return Err(IdnParseError::MissingNumber {
                position: NUMBER_START,
            });
        }
        if digits > 4 {
            return Err(IdnParseError::NumberTooLong);
        }
        let number = bytes
            .get(NUMBER_START..NUMBER_START + digits)
            .unwrap_or_default()
            .iter()
            .fold(0u16, |acc, d| acc * 10 + u16::from(d - b'0'));
        let end = NUMBER_START + digits;
        if end < bytes.len() {
            return Err(IdnParseError::TrailingText { position: end });
        }
        Idn::new(kind, parameter_set, number).map_err(|error| match error {
            IdnError::ParameterSetOutOfRange(set) => IdnParseError::ParameterSetOutOfRange(set),
            IdnError::NumberOutOfRange(number) => IdnParseError::NumberOutOfRange(number),
        })
    }
}

fn expect_separator(bytes: &[u8], position: usize) -> Result<(), IdnParseError> {
    match bytes.get(position) {
        Some(b'-') => Ok(()),
        _ => Err(IdnParseError::MissingSeparator { position }),
    }
}

/// The data block element addressed through the service channel (MDT control word bits 5–3).
///
/// sercos-telegrams.md, MDT control word bits 5, 4, 3: "000 Service channel not active,
/// 001 IDN (number) of the op data, 010 Name of operation data, 011 Attribute of op data,
/// 100 Units of op data, 101 Min input value, 110 Max input value, 111 Operation data".
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum Element {
    /// 0: service channel closed / not active (closes the channel or breaks a transmission).
    ServiceChannelClosed = 0,
    /// 1: the IDN (opens the service channel for a new IDN).
    Idn = 1,
    /// 2: the name.
    Name = 2,
    /// 3: the attribute.
    Attribute = 3,
    /// 4: the unit.
    Unit = 4,
    /// 5: the minimum input value.
    Minimum = 5,
    /// 6: the maximum input value.
    Maximum = 6,
    /// 7: the operation data.
    OperationData = 7,
}

/// A number above 7 is not a data block element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[error("data block element {0} is out of range (0-7)")]
pub struct ElementOutOfRange(pub u8);

impl Element {
    /// All elements, 0 to 7.
    pub const ALL: [Element; 8] = [
        Element::ServiceChannelClosed,
        Element::Idn,
        Element::Name,
        Element::Attribute,
        Element::Unit,
        Element::Minimum,
        Element::Maximum,
        Element::OperationData,
    ];

    /// The element from its three bits; higher bits are ignored.
    pub const fn from_bits(bits: u8) -> Element {
        match bits & 0b111 {
            0 => Element::ServiceChannelClosed,
            1 => Element::Idn,
            2 => Element::Name,
            3 => Element::Attribute,
            4 => Element::Unit,
            5 => Element::Minimum,
            6 => Element::Maximum,
            _ => Element::OperationData,
        }
    }

    /// The element's number, 0–7.
    pub const fn bits(self) -> u8 {
        self as u8
    }

    /// A short lower-case name, e.g. `operation data`.
    pub const fn name(self) -> &'static str {
        match self {
            Element::ServiceChannelClosed => "closed",
            Element::Idn => "IDN",
            Element::Name => "name",
            Element::Attribute => "attribute",
            Element::Unit => "unit",
            Element::Minimum => "minimum",
            Element::Maximum => "maximum",
            Element::OperationData => "operation data",
        }
    }
}

impl TryFrom<u8> for Element {
    type Error = ElementOutOfRange;

    fn try_from(value: u8) -> Result<Element, ElementOutOfRange> {
        if value > 7 {
            Err(ElementOutOfRange(value))
        } else {
            Ok(Element::from_bits(value))
        }
    }
}

impl From<Element> for u8 {
    fn from(element: Element) -> u8 {
        element.bits()
    }
}

impl fmt::Display for Element {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_of_p_3_0123() {
        // sercos-facts.md, IDNs: bit 15 = P, bits 14–12 = set, bits 11–0 = number.
        let idn = Idn::from_raw(0x8000 | (3 << 12) | 123);
        assert_eq!(idn.kind(), IdnKind::Product);
        assert_eq!(idn.parameter_set(), 3);
        assert_eq!(idn.number(), 123);
        assert_eq!(Idn::new(IdnKind::Product, 3, 123), Ok(idn));
    }

    #[test]
    fn new_rejects_out_of_range_parts() {
        assert_eq!(
            Idn::new(IdnKind::Standard, 8, 1),
            Err(IdnError::ParameterSetOutOfRange(8))
        );
        assert_eq!(
            Idn::new(IdnKind::Standard, 0, 4096),
            Err(IdnError::NumberOutOfRange(4096))
        );
    }

    #[test]
    fn element_bits_round_trip() {
        // sercos-telegrams.md, MDT control word bits 5–3: element 000–111.
        for (bits, element) in Element::ALL.iter().enumerate() {
            assert_eq!(usize::from(element.bits()), bits);
            assert_eq!(Element::try_from(element.bits()), Ok(*element));
        }
        assert_eq!(Element::try_from(8), Err(ElementOutOfRange(8)));
    }
}
