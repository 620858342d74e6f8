//! The 32-bit IDN attribute (data block element 3) and the operation data it describes.
//!
//! sercos-facts.md, IDNs, "Attribute (32 bit)": bits 15–0 conversion factor; bits 18–16 data
//! length (1 = 2 bytes, 2 = 4 bytes, 3 = 8 bytes, 4–7 = variable-length list of 1-, 2-, 4-,
//! 8-byte elements); bit 19 procedure command; bits 22–20 type/display (0 binary, 1 unsigned
//! decimal, 2 signed decimal, 3 hexadecimal, 4 text, 5 IDN, 6 floating point); bits 27–24
//! decimal places; bits 30–28 write protection in phase 2, 3, 4.
//!
//! Operation data travels through the service channel as 16-bit words. Fixed-length data is
//! 1, 2 or 4 words, low word first; variable-length data is the current length in bytes, the
//! maximum length in bytes, then the data bytes packed low byte first (sercos-facts.md,
//! "Variable-length data"). [`Value`] is the typed reading of those words.
//!
//! Readings chosen where the sources are silent (docs/spec-notes.md, "IDN attributes"):
//! data length 0 is reserved and holds no interpretable data; bits 23 and 31 are reserved and
//! kept; the conversion factor multiplies integer values for display when it is above 1.

use core::fmt;

use crate::idn::Idn;
use crate::telegram::CommunicationPhase;

#[cfg(feature = "alloc")]
use alloc::vec::Vec;

/// Bits 18–16 of the attribute: the length of the operation data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum DataLength {
    /// 0: reserved; no interpretable operation data (docs/spec-notes.md, "IDN attributes").
    Reserved = 0,
    /// 1: two bytes (one word).
    TwoBytes = 1,
    /// 2: four bytes (two words).
    FourBytes = 2,
    /// 3: eight bytes (four words).
    EightBytes = 3,
    /// 4: variable-length list of 1-byte elements (text, byte strings).
    VariableBytes = 4,
    /// 5: variable-length list of 2-byte elements (e.g. IDN lists).
    VariableWords = 5,
    /// 6: variable-length list of 4-byte elements.
    VariableLongs = 6,
    /// 7: variable-length list of 8-byte elements.
    VariableDoubleLongs = 7,
}

impl DataLength {
    /// The length from its three bits; higher bits are ignored.
    pub const fn from_bits(bits: u8) -> DataLength {
        match bits & 0b111 {
            0 => DataLength::Reserved,
            1 => DataLength::TwoBytes,
            2 => DataLength::FourBytes,
            3 => DataLength::EightBytes,
            4 => DataLength::VariableBytes,
            5 => DataLength::VariableWords,
            6 => DataLength::VariableLongs,
            _ => DataLength::VariableDoubleLongs,
        }
    }

    /// The three bits, 0–7.
    pub const fn bits(self) -> u8 {
        self as u8
    }

    /// `true` for the variable-length lists (4–7).
    pub const fn is_variable(self) -> bool {
        (self as u8) >= 4
    }

    /// Size in bytes of one value (fixed lengths) or one list element (variable lengths);
    /// 0 for [`DataLength::Reserved`].
    pub const fn element_bytes(self) -> usize {
        match self {
            DataLength::Reserved => 0,
            DataLength::VariableBytes => 1,
            DataLength::TwoBytes | DataLength::VariableWords => 2,
            DataLength::FourBytes | DataLength::VariableLongs => 4,
            DataLength::EightBytes | DataLength::VariableDoubleLongs => 8,
        }
    }
}

/// Bits 22–20 of the attribute: how the operation data is typed and shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum DisplayFormat {
    /// 0: binary.
    Binary = 0,
    /// 1: unsigned decimal.
    UnsignedDecimal = 1,
    /// 2: signed decimal.
    SignedDecimal = 2,
    /// 3: hexadecimal.
    Hexadecimal = 3,
    /// 4: text.
    Text = 4,
    /// 5: IDN.
    Idn = 5,
    /// 6: floating point (IEEE 754, 4 or 8 bytes).
    Float = 6,
    /// 7: not defined by the sources; shown as hexadecimal.
    Reserved = 7,
}

impl DisplayFormat {
    /// The format from its three bits; higher bits are ignored.
    pub const fn from_bits(bits: u8) -> DisplayFormat {
        match bits & 0b111 {
            0 => DisplayFormat::Binary,
            1 => DisplayFormat::UnsignedDecimal,
            2 => DisplayFormat::SignedDecimal,
            3 => DisplayFormat::Hexadecimal,
            4 => DisplayFormat::Text,
            5 => DisplayFormat::Idn,
            6 => DisplayFormat::Float,
            _ => DisplayFormat::Reserved,
        }
    }

    /// The three bits, 0–7.
    pub const fn bits(self) -> u8 {
        self as u8
    }
}

/// The 32-bit attribute of an IDN (data block element 3). Every `u32` is representable.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "u32", into = "u32")
)]
pub struct Attribute(u32);

impl Attribute {
    /// Bits 15–0: conversion factor (sercos-facts.md, attribute).
    pub const CONVERSION_FACTOR: u32 = 0xFFFF;
    /// Bits 18–16: data length.
    pub const DATA_LENGTH: u32 = 0b111 << 16;
    /// Bit 19: procedure command.
    pub const PROCEDURE_COMMAND: u32 = 1 << 19;
    /// Bits 22–20: type / display format.
    pub const DISPLAY_FORMAT: u32 = 0b111 << 20;
    /// Bits 27–24: decimal places.
    pub const DECIMAL_PLACES: u32 = 0xF << 24;
    /// Bit 28: write-protected in phase 2.
    pub const WRITE_PROTECTED_PHASE_2: u32 = 1 << 28;
    /// Bit 29: write-protected in phase 3.
    pub const WRITE_PROTECTED_PHASE_3: u32 = 1 << 29;
    /// Bit 30: write-protected in phase 4.
    pub const WRITE_PROTECTED_PHASE_4: u32 = 1 << 30;
    /// Bits 23 and 31: not described by the sources; kept as they are.
    pub const RESERVED: u32 = (1 << 23) | (1 << 31);

    /// The attribute from its 32-bit value.
    pub const fn from_raw(raw: u32) -> Attribute {
        Attribute(raw)
    }

    /// The 32-bit value.
    pub const fn raw(self) -> u32 {
        self.0
    }

    /// The attribute as the two service-channel words, low word first.
    pub const fn to_words(self) -> [u16; 2] {
        [self.0 as u16, (self.0 >> 16) as u16]
    }

    /// The attribute from two service-channel words, low word first.
    pub const fn from_words(words: [u16; 2]) -> Attribute {
        Attribute((words[0] as u32) | ((words[1] as u32) << 16))
    }

    /// A plain attribute: conversion factor 1, the given length and format, no decimal
    /// places, not a command, writable in every phase.
    pub const fn new(length: DataLength, format: DisplayFormat) -> Attribute {
        Attribute(1)
            .with_data_length(length)
            .with_display_format(format)
    }

    /// Bits 15–0, the conversion factor.
    pub const fn conversion_factor(self) -> u16 {
        self.0 as u16
    }

    /// Bits 18–16, the data length.
    pub const fn data_length(self) -> DataLength {
        DataLength::from_bits((self.0 >> 16) as u8)
    }

    /// Bit 19, procedure command.
    pub const fn is_procedure_command(self) -> bool {
        self.0 & Self::PROCEDURE_COMMAND != 0
    }

    /// Bits 22–20, the type / display format.
    pub const fn display_format(self) -> DisplayFormat {
        DisplayFormat::from_bits((self.0 >> 20) as u8)
    }

    /// Bits 27–24, the number of decimal places (0–15).
    pub const fn decimal_places(self) -> u8 {
        ((self.0 >> 24) & 0xF) as u8
    }

    /// Bits 30–28: whether the operation data is write-protected in `phase`. Phases 0 and 1
    /// have no protection bit: the service channel does not run there, so nothing is
    /// protected by the attribute (docs/spec-notes.md, "IDN attributes").
    pub const fn write_protected_in(self, phase: CommunicationPhase) -> bool {
        let bit = match phase {
            CommunicationPhase::Phase0 | CommunicationPhase::Phase1 => return false,
            CommunicationPhase::Phase2 => Self::WRITE_PROTECTED_PHASE_2,
            CommunicationPhase::Phase3 => Self::WRITE_PROTECTED_PHASE_3,
            CommunicationPhase::Phase4 => Self::WRITE_PROTECTED_PHASE_4,
        };
        self.0 & bit != 0
    }

    /// With the conversion factor (bits 15–0) replaced.
    pub const fn with_conversion_factor(self, factor: u16) -> Attribute {
        Attribute((self.0 & !Self::CONVERSION_FACTOR) | factor as u32)
    }

    /// With the data length (bits 18–16) replaced.
    pub const fn with_data_length(self, length: DataLength) -> Attribute {
        Attribute((self.0 & !Self::DATA_LENGTH) | ((length.bits() as u32) << 16))
    }

    /// With bit 19, procedure command, set or cleared.
    pub const fn with_procedure_command(self, command: bool) -> Attribute {
        if command {
            Attribute(self.0 | Self::PROCEDURE_COMMAND)
        } else {
            Attribute(self.0 & !Self::PROCEDURE_COMMAND)
        }
    }

    /// With the display format (bits 22–20) replaced.
    pub const fn with_display_format(self, format: DisplayFormat) -> Attribute {
        Attribute((self.0 & !Self::DISPLAY_FORMAT) | ((format.bits() as u32) << 20))
    }

    /// With the decimal places (bits 27–24) replaced; values above 15 are cut to 4 bits.
    pub const fn with_decimal_places(self, places: u8) -> Attribute {
        Attribute((self.0 & !Self::DECIMAL_PLACES) | (((places & 0xF) as u32) << 24))
    }

    /// With write protection in phases 2, 3 and 4 (bits 28, 29, 30) replaced.
    pub const fn with_write_protection(
        self,
        phase2: bool,
        phase3: bool,
        phase4: bool,
    ) -> Attribute {
        let mut raw = self.0
            & !(Self::WRITE_PROTECTED_PHASE_2
                | Self::WRITE_PROTECTED_PHASE_3
                | Self::WRITE_PROTECTED_PHASE_4);
        if phase2 {
            raw |= Self::WRITE_PROTECTED_PHASE_2;
        }
        if phase3 {
            raw |= Self::WRITE_PROTECTED_PHASE_3;
        }
        if phase4 {
            raw |= Self::WRITE_PROTECTED_PHASE_4;
        }
        Attribute(raw)
    }

    /// Number of words of fixed-length operation data (1, 2 or 4), or `None` for variable
    /// lengths and the reserved length 0.
    pub const fn fixed_words(self) -> Option<usize> {
        match self.data_length() {
            DataLength::TwoBytes => Some(1),
            DataLength::FourBytes => Some(2),
            DataLength::EightBytes => Some(4),
            _ => None,
        }
    }

    /// Decodes fixed-length operation data (1, 2 or 4 words, low word first) into a value.
    ///
    /// Variable-length data needs the `alloc` feature: see [`Attribute::decode`].
    pub fn decode_fixed(self, words: &[u16]) -> Result<Value, AttributeError> {
        let count = self.fixed_words().ok_or(AttributeError::NotFixedLength)?;
        check_word_count(words.len(), count)?;
        let raw = words
            .iter()
            .take(count)
            .rev()
            .fold(0u64, |acc, &w| (acc << 16) | u64::from(w));
        Ok(self.value_from_bits(raw, count * 2))
    }

    /// Encodes a fixed-length value into its words, low word first. Returns the word array
    /// and how many of its words are used (1, 2 or 4).
    pub fn encode_fixed(self, value: &Value) -> Result<([u16; 4], usize), AttributeError> {
        let count = self.fixed_words().ok_or(AttributeError::NotFixedLength)?;
        let raw = self.bits_from_value(value, count * 2)?;
        let mut words = [0u16; 4];
        for (i, word) in words.iter_mut().enumerate().take(count) {
            *word = (raw >> (16 * i)) as u16;
        }
        Ok((words, count))
    }

    /// The typed reading of `size` bytes of raw data (little-endian, zero-extended).
    fn value_from_bits(self, raw: u64, size: usize) -> Value {
        match self.display_format() {
            DisplayFormat::SignedDecimal => Value::Signed(sign_extend(raw, size)),
            DisplayFormat::Float if size == 4 => {
                Value::Float(f64::from(f32::from_bits(raw as u32)))
            }
            DisplayFormat::Float if size == 8 => Value::Float(f64::from_bits(raw)),
            DisplayFormat::Idn if size == 2 => Value::Idn(Idn::from_raw(raw as u16)),
            _ => Value::Unsigned(raw),
        }
    }

    /// The raw little-endian bits of `value` for a field of `size` bytes, checked to fit: a
    /// signed-decimal field takes the two's-complement range, every other integer field the
    /// unsigned range.
    fn bits_from_value(self, value: &Value, size: usize) -> Result<u64, AttributeError> {
        let format = self.display_format();
        if format == DisplayFormat::Float {
            return match (value, size) {
                (Value::Float(f), 4) => Ok(u64::from((*f as f32).to_bits())),
                (Value::Float(f), 8) => Ok(f.to_bits()),
                _ => Err(AttributeError::WrongType),
            };
        }
        let number = value.as_i128().ok_or(AttributeError::WrongType)?;
        if matches!(value, Value::Idn(_)) && size != 2 {
            return Err(AttributeError::WrongType);
        }
        let bits = (size * 8) as u32;
        let (min, max) = if format == DisplayFormat::SignedDecimal {
            (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
        } else {
            (0, (1i128 << bits) - 1)
        };
        if number < min || number > max {
            return Err(AttributeError::OutOfRange);
        }
        Ok(number as u64)
    }

    /// Formats `value` for people according to this attribute: decimal places, sign,
    /// hexadecimal, binary, text, IDNs and lists.
    pub fn display(self, value: &Value) -> ValueDisplay<'_> {
        ValueDisplay {
            attribute: self,
            value,
        }
    }
}

fn check_word_count(found: usize, expected: usize) -> Result<(), AttributeError> {
    if found < expected {
        Err(AttributeError::TooShort { expected, found })
    } else if found > expected {
        Err(AttributeError::TooLong { expected, found })
    } else {
        Ok(())
    }
}

fn sign_extend(raw: u64, size: usize) -> i64 {
    let shift = 64u32.saturating_sub((size as u32).saturating_mul(8));
    if shift >= 64 {
        return 0;
    }
    ((raw << shift) as i64) >> shift
}

impl From<u32> for Attribute {
    fn from(raw: u32) -> Attribute {
        Attribute(raw)
    }
}

impl From<Attribute> for u32 {
    fn from(attribute: Attribute) -> u32 {
        attribute.0
    }
}

impl fmt::Debug for Attribute {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Attribute({self})")
    }
}

/// `XXXXXXXXH (length, format, places, factor, command, protection)`.
impl fmt::Display for Attribute {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:08X}H ({:?}, {:?}, {} decimal places, factor {}",
            self.0,
            self.data_length(),
            self.display_format(),
            self.decimal_places(),
            self.conversion_factor()
        )?;
        if self.is_procedure_command() {
            f.write_str(", procedure command")?;
        }
        for (phase, bit) in [
            (2, Self::WRITE_PROTECTED_PHASE_2),
            (3, Self::WRITE_PROTECTED_PHASE_3),
            (4, Self::WRITE_PROTECTED_PHASE_4),
        ] {
            if self.0 & bit != 0 {
                write!(f, ", write-protected in phase {phase}")?;
            }
        }
        f.write_str(")")
    }
}

/// Why operation data words could not be read or written as a value of an attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum AttributeError {
    /// Data length 0 is reserved: there is no defined layout.
    #[error("data length 0 is reserved")]
    ReservedLength,
    /// A fixed-length operation was used on variable-length data.
    #[error("the attribute describes variable-length data")]
    NotFixedLength,
    /// Fewer words than the attribute requires.
    #[error("operation data too short: {found} words, expected {expected}")]
    TooShort {
        /// Words required.
        expected: usize,
        /// Words given.
        found: usize,
    },
    /// More words than the attribute allows.
    #[error("operation data too long: {found} words, expected {expected}")]
    TooLong {
        /// Words allowed.
        expected: usize,
        /// Words given.
        found: usize,
    },
    /// The variable-length header is inconsistent: the current length exceeds the maximum,
    /// or is not a whole number of list elements.
    #[error("variable-length data: current length {current} bytes, maximum {maximum} bytes")]
    BadVariableLength {
        /// Current length in bytes (first word).
        current: u16,
        /// Maximum length in bytes (second word).
        maximum: u16,
    },
    /// The value's type does not match the attribute (e.g. text for a number).
    #[error("the value does not match the attribute's type")]
    WrongType,
    /// The value does not fit the attribute's data length.
    #[error("the value does not fit the attribute's data length")]
    OutOfRange,
}

/// The typed reading of operation data (or of a minimum / maximum).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Value {
    /// Binary, unsigned decimal and hexadecimal data, zero-extended.
    Unsigned(u64),
    /// Signed decimal data, sign-extended.
    Signed(i64),
    /// Floating-point data (4-byte values widened).
    Float(f64),
    /// One IDN (2-byte data with display format IDN).
    Idn(Idn),
    /// Text or another 1-byte list, as bytes (not necessarily UTF-8).
    #[cfg(feature = "alloc")]
    Text(Vec<u8>),
    /// A list of IDNs (2-byte list with display format IDN).
    #[cfg(feature = "alloc")]
    IdnList(Vec<Idn>),
    /// A list of unsigned numbers (binary, unsigned decimal or hexadecimal elements).
    #[cfg(feature = "alloc")]
    UnsignedList(Vec<u64>),
    /// A list of signed numbers.
    #[cfg(feature = "alloc")]
    SignedList(Vec<i64>),
    /// A list of floating-point numbers.
    #[cfg(feature = "alloc")]
    FloatList(Vec<f64>),
}

impl Value {
    /// The value as a signed 128-bit number when it is a single number (for comparing with a
    /// minimum and maximum); `None` for floats, text and lists.
    pub fn as_i128(&self) -> Option<i128> {
        match self {
            Value::Unsigned(v) => Some(i128::from(*v)),
            Value::Signed(v) => Some(i128::from(*v)),
            Value::Idn(idn) => Some(i128::from(idn.raw())),
            _ => None,
        }
    }

    /// The value as a float when it is a single number.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Float(v) => Some(*v),
            other => other.as_i128().map(|v| v as f64),
        }
    }
}

#[cfg(feature = "alloc")]
impl Attribute {
    /// Decodes operation data words into a value: fixed-length data (1, 2 or 4 words, low
    /// word first) or variable-length data (current length in bytes, maximum length in bytes,
    /// then the data packed low byte first).
    pub fn decode(self, words: &[u16]) -> Result<Value, AttributeError> {
        let length = self.data_length();
        if length == DataLength::Reserved {
            return Err(AttributeError::ReservedLength);
        }
        if !length.is_variable() {
            return self.decode_fixed(words);
        }
        let (current, maximum, bytes) = split_variable(words)?;
        let size = length.element_bytes();
        if current > maximum || usize::from(current) % size != 0 {
            return Err(AttributeError::BadVariableLength { current, maximum });
        }
        let elements = bytes.chunks_exact(size).map(|chunk| {
            chunk
                .iter()
                .rev()
                .fold(0u64, |acc, &b| (acc << 8) | u64::from(b))
        });
        Ok(match (self.display_format(), length) {
            (_, DataLength::VariableBytes) => Value::Text(bytes),
            (DisplayFormat::Idn, DataLength::VariableWords) => {
                Value::IdnList(elements.map(|e| Idn::from_raw(e as u16)).collect())
            }
            (DisplayFormat::SignedDecimal, _) => {
                Value::SignedList(elements.map(|e| sign_extend(e, size)).collect())
            }
            (DisplayFormat::Float, DataLength::VariableLongs) => Value::FloatList(
                elements
                    .map(|e| f64::from(f32::from_bits(e as u32)))
                    .collect(),
            ),
            (DisplayFormat::Float, DataLength::VariableDoubleLongs) => {
                Value::FloatList(elements.map(f64::from_bits).collect())
            }
            _ => Value::UnsignedList(elements.collect()),
        })
    }

    /// Encodes a value into operation data words. For variable-length data `maximum_bytes`
    /// is the maximum length written in the second word (raised to the current length if
    /// smaller); it is ignored for fixed-length data.
    pub fn encode(self, value: &Value, maximum_bytes: u16) -> Result<Vec<u16>, AttributeError> {
        let length = self.data_length();
        if length == DataLength::Reserved {
            return Err(AttributeError::ReservedLength);
        }
        if !length.is_variable() {
            let (words, count) = self.encode_fixed(value)?;
            return Ok(words.get(..count).unwrap_or_default().to_vec());
        }
        let size = length.element_bytes();
        let mut bytes: Vec<u8> = Vec::new();
        let mut push =
            |raw: u64| bytes.extend_from_slice(raw.to_le_bytes().get(..size).unwrap_or_default());
        match (value, length) {
            (Value::Text(text), DataLength::VariableBytes) => {
                text.iter().for_each(|&b| push(u64::from(b)))
            }
            (Value::UnsignedList(list), _) if self.display_format() != DisplayFormat::Float => {
                for &v in list {
                    if size < 8 && v >> (size * 8) != 0 {
                        return Err(AttributeError::OutOfRange);
                    }
                    push(v);
                }
            }
            (Value::SignedList(list), _)
                if self.display_format() == DisplayFormat::SignedDecimal =>
            {
                for &v in list {
                    if size < 8 {
                        let half = 1i64 << (size * 8 - 1);
                        if v < -half || v >= half {
                            return Err(AttributeError::OutOfRange);
                        }
                    }
                    push(v as u64);
                }
            }
            (Value::IdnList(list), DataLength::VariableWords) => {
                list.iter().for_each(|idn| push(u64::from(idn.raw())))
            }
            (Value::FloatList(list), DataLength::VariableLongs)
                if self.display_format() == DisplayFormat::Float =>
            {
                list.iter()
                    .for_each(|&v| push(u64::from((v as f32).to_bits())))
            }
            (Value::FloatList(list), DataLength::VariableDoubleLongs)
                if self.display_format() == DisplayFormat::Float =>
            {
                list.iter().for_each(|&v| push(v.to_bits()))
            }
            _ => return Err(AttributeError::WrongType),
        }
        let current = u16::try_from(bytes.len()).map_err(|_| AttributeError::OutOfRange)?;
        if current > u16::MAX - 1 {
            return Err(AttributeError::OutOfRange);
        }
        let maximum = maximum_bytes.max(current);
        let mut words = Vec::with_capacity(2 + bytes.len().div_ceil(2));
        words.push(current);
        words.push(maximum);
        words.extend(bytes.chunks(2).map(|pair| {
            u16::from_le_bytes([
                pair.first().copied().unwrap_or(0),
                pair.get(1).copied().unwrap_or(0),
            ])
        }));
        Ok(words)
    }
}

/// Splits variable-length data into (current length, maximum length, data bytes), checking
/// that the words hold exactly the current length (sercos-facts.md, variable-length data).
#[cfg(feature = "alloc")]
fn split_variable(words: &[u16]) -> Result<(u16, u16, Vec<u8>), AttributeError> {
    let (&current, rest) = words.split_first().ok_or(AttributeError::TooShort {
        expected: 2,
        found: 0,
    })?;
    let (&maximum, data) = rest.split_first().ok_or(AttributeError::TooShort {
        expected: 2,
        found: 1,
    })?;
    let expected = 2 + usize::from(current).div_ceil(2);
    check_word_count(words.len(), expected)?;
    let bytes = data
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take(usize::from(current))
        .collect();
    Ok((current, maximum, bytes))
}

/// A value formatted by its attribute; made by [`Attribute::display`].
pub struct ValueDisplay<'a> {
    attribute: Attribute,
    value: &'a Value,
}

impl ValueDisplay<'_> {
    fn number(&self, f: &mut fmt::Formatter<'_>, value: i128, size: usize) -> fmt::Result {
        let attribute = self.attribute;
        match attribute.display_format() {
            DisplayFormat::Binary => {
                let width = size * 8;
                write!(f, "0b{:0width$b}", value as u128 & mask(size))
            }
            DisplayFormat::Hexadecimal | DisplayFormat::Reserved => {
                let width = size * 2;
                write!(f, "0x{:0width$X}", value as u128 & mask(size))
            }
            DisplayFormat::Idn if size == 2 => write!(f, "{}", Idn::from_raw(value as u16)),
            _ => {
                let factor = attribute.conversion_factor();
                // docs/spec-notes.md, "IDN attributes": a factor above 1 multiplies the value.
                let scaled = if factor > 1 {
                    value.saturating_mul(i128::from(factor))
                } else {
                    value
                };
                write_decimal(f, scaled, attribute.decimal_places())
            }
        }
    }
}

fn mask(size: usize) -> u128 {
    if size >= 16 {
        u128::MAX
    } else {
        (1u128 << (size * 8)) - 1
    }
}

/// Writes `value / 10^places` exactly, e.g. 12345 with 3 places as `12.345`.
fn write_decimal(f: &mut fmt::Formatter<'_>, value: i128, places: u8) -> fmt::Result {
    if places == 0 {
        return write!(f, "{value}");
    }
    let divisor = 10u128.pow(u32::from(places));
    let magnitude = value.unsigned_abs();
    let sign = if value < 0 { "-" } else { "" };
    let width = usize::from(places);
    write!(
        f,
        "{sign}{}.{:0width$}",
        magnitude / divisor,
        magnitude % divisor
    )
}

impl fmt::Display for ValueDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let size = self.attribute.data_length().element_bytes().max(1);
        let places = usize::from(self.attribute.decimal_places());
        match self.value {
            Value::Unsigned(v) => self.number(f, i128::from(*v), size),
            Value::Signed(v) => self.number(f, i128::from(*v), size),
            Value::Idn(idn) => write!(f, "{idn}"),
            Value::Float(v) => write!(f, "{v:.places$}"),
            #[cfg(feature = "alloc")]
            Value::Text(bytes) => {
                if self.attribute.display_format() == DisplayFormat::Text {
                    for chunk in bytes.utf8_chunks() {
                        f.write_str(chunk.valid())?;
                        for byte in chunk.invalid() {
                            write!(f, "\\x{byte:02X}")?;
                        }
                    }
                    Ok(())
                } else {
                    self.list(f, bytes.iter(), |f, b| self.number(f, i128::from(*b), 1))
                }
            }
            #[cfg(feature = "alloc")]
            Value::IdnList(list) => self.list(f, list.iter(), |f, idn| write!(f, "{idn}")),
            #[cfg(feature = "alloc")]
            Value::UnsignedList(list) => {
                self.list(f, list.iter(), |f, v| self.number(f, i128::from(*v), size))
            }
            #[cfg(feature = "alloc")]
            Value::SignedList(list) => {
                self.list(f, list.iter(), |f, v| self.number(f, i128::from(*v), size))
            }
            #[cfg(feature = "alloc")]
            Value::FloatList(list) => self.list(f, list.iter(), |f, v| write!(f, "{v:.places$}")),
        }
    }
}

impl ValueDisplay<'_> {
    #[cfg(feature = "alloc")]
    fn list<T>(
        &self,
        f: &mut fmt::Formatter<'_>,
        items: impl Iterator<Item = T>,
        mut each: impl FnMut(&mut fmt::Formatter<'_>, T) -> fmt::Result,
    ) -> fmt::Result {
        f.write_str("[")?;
        for (i, item) in items.enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            each(f, item)?;
        }
        f.write_str("]")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(feature = "alloc")]
    use alloc::string::ToString;

    #[test]
    fn attribute_fields() {
        // sercos-facts.md, attribute: bits 18–16 length, 19 command, 22–20 format,
        // 27–24 places, 30–28 protection in phases 2, 3, 4.
        let attribute = Attribute::from_raw(0x332A_0001);
        assert_eq!(attribute.conversion_factor(), 1);
        assert_eq!(attribute.data_length(), DataLength::FourBytes);
        assert!(attribute.is_procedure_command());
        assert_eq!(attribute.display_format(), DisplayFormat::SignedDecimal);
        assert_eq!(attribute.decimal_places(), 3);
        assert!(attribute.write_protected_in(CommunicationPhase::Phase2));
        assert!(attribute.write_protected_in(CommunicationPhase::Phase3));
        assert!(!attribute.write_protected_in(CommunicationPhase::Phase4));
        let rebuilt = Attribute::new(DataLength::FourBytes, DisplayFormat::SignedDecimal)
            .with_procedure_command(true)
            .with_decimal_places(3)
            .with_write_protection(true, true, false);
        assert_eq!(rebuilt, attribute);
        assert_eq!(Attribute::from_words(attribute.to_words()), attribute);
    }

    #[test]
    fn fixed_values_low_word_first() {
        // sercos-facts.md: fixed-length values in 1/2/4 words, low word first.
        let attribute = Attribute::new(DataLength::FourBytes, DisplayFormat::SignedDecimal);
        let value = attribute.decode_fixed(&[0xFFFE, 0xFFFF]);
        assert_eq!(value, Ok(Value::Signed(-2)));
        let (words, count) = attribute
            .encode_fixed(&Value::Signed(-70_000))
            .unwrap_or_default();
        assert_eq!(count, 2);
        assert_eq!(
            words[..2],
            [
                (-70_000i32 as u32) as u16,
                ((-70_000i32 as u32) >> 16) as u16
            ]
        );
        assert_eq!(
            attribute.encode_fixed(&Value::Signed(1 << 31)),
            Err(AttributeError::OutOfRange)
        );
        let short = Attribute::new(DataLength::TwoBytes, DisplayFormat::UnsignedDecimal);
        assert_eq!(
            short.decode_fixed(&[1, 2]),
            Err(AttributeError::TooLong {
                expected: 1,
                found: 2
            })
        );
        assert_eq!(
            short.encode_fixed(&Value::Unsigned(65_536)),
            Err(AttributeError::OutOfRange)
        );
    }

    #[test]
    fn float_round_trip() {
        let attribute = Attribute::new(DataLength::FourBytes, DisplayFormat::Float);
        let (words, count) = attribute
            .encode_fixed(&Value::Float(1.5))
            .unwrap_or_default();
        assert_eq!(
            attribute.decode_fixed(&words[..count]),
            Ok(Value::Float(1.5))
        );
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn decimal_places_and_sign() {
        // sercos-facts.md: bits 27–24 decimal places, type 2 signed decimal.
        let attribute = Attribute::new(DataLength::FourBytes, DisplayFormat::SignedDecimal)
            .with_decimal_places(4);
        assert_eq!(
            attribute.display(&Value::Signed(-12_345)).to_string(),
            "-1.2345"
        );
        assert_eq!(attribute.display(&Value::Signed(5)).to_string(), "0.0005");
        let hex = Attribute::new(DataLength::TwoBytes, DisplayFormat::Hexadecimal);
        assert_eq!(hex.display(&Value::Unsigned(0x7D0)).to_string(), "0x07D0");
        let binary = Attribute::new(DataLength::TwoBytes, DisplayFormat::Binary);
        assert_eq!(
            binary.display(&Value::Unsigned(5)).to_string(),
            "0b0000000000000101"
        );
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn variable_idn_list_as_in_capture() {
        // The captures' write of S-0-0016: current 6 bytes, maximum 6, then three IDNs.
        let attribute = Attribute::new(DataLength::VariableWords, DisplayFormat::Idn);
        let words = [6, 6, 0x000B, 0x0033, 0x8013];
        let value = attribute.decode(&words);
        let expected = Value::IdnList(alloc::vec![
            Idn::from_raw(11),
            Idn::from_raw(51),
            Idn::from_raw(0x8013)
        ]);
        assert_eq!(value, Ok(expected.clone()));
        assert_eq!(attribute.encode(&expected, 6), Ok(words.to_vec()));
        assert_eq!(
            attribute.display(&expected).to_string(),
            "[S-0-0011, S-0-0051, P-0-0019]"
        );
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn text_odd_length_and_bad_headers() {
        let attribute = Attribute::new(DataLength::VariableBytes, DisplayFormat::Text);
        let words = attribute
            .encode(&Value::Text(b"abc".to_vec()), 10)
            .unwrap_or_default();
        assert_eq!(words, [3, 10, u16::from_le_bytes(*b"ab"), u16::from(b'c')]);
        assert_eq!(attribute.decode(&words), Ok(Value::Text(b"abc".to_vec())));
        assert_eq!(
            attribute.display(&Value::Text(b"abc".to_vec())).to_string(),
            "abc"
        );
        // Current above maximum.
        assert_eq!(
            attribute.decode(&[4, 2, 0, 0]),
            Err(AttributeError::BadVariableLength {
                current: 4,
                maximum: 2
            })
        );
        // Words missing for the current length.
        assert_eq!(
            attribute.decode(&[4, 4, 0]),
            Err(AttributeError::TooShort {
                expected: 4,
                found: 3
            })
        );
        let list = Attribute::new(DataLength::VariableLongs, DisplayFormat::UnsignedDecimal);
        assert_eq!(
            list.decode(&[2, 4, 0]),
            Err(AttributeError::BadVariableLength {
                current: 2,
                maximum: 4
            })
        );
        let reserved = Attribute::new(DataLength::Reserved, DisplayFormat::Binary);
        assert_eq!(reserved.decode(&[0]), Err(AttributeError::ReservedLength));
    }
}
