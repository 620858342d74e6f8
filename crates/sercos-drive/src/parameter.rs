//! One IDN of the drive: its data block elements 1–7.
//!
//! sercos-facts.md, IDNs: "Data block elements: 1 IDN, 2 name, 3 attribute, 4 unit,
//! 5 minimum, 6 maximum, 7 operation data".

use sercos_wire::attribute::{Attribute, AttributeError, DataLength, Value};
use sercos_wire::idn::Idn;
use sercos_wire::idn_catalog::{CatalogDefault, IdnInfo};

/// One parameter of the drive's database.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// Element 1, the IDN.
    pub idn: Idn,
    /// Element 2, the name.
    pub name: String,
    /// Element 3, the attribute.
    pub attribute: Attribute,
    /// Element 4, the unit.
    pub unit: String,
    /// Element 5, the minimum input value (fixed-length numbers only).
    pub min: Option<Value>,
    /// Element 6, the maximum input value (fixed-length numbers only).
    pub max: Option<Value>,
    /// Maximum length in bytes of variable-length operation data (0 for fixed length).
    pub max_len: u16,
    /// Element 7, the operation data as service-channel words (variable-length data
    /// includes its two length words).
    words: Vec<u16>,
}

impl Parameter {
    /// A parameter with the given description and operation data, checked to fit the
    /// attribute (and, for variable-length data, `max_len`).
    pub fn new(
        idn: Idn,
        name: impl Into<String>,
        attribute: Attribute,
        unit: impl Into<String>,
        max_len: u16,
        value: &Value,
    ) -> Result<Parameter, AttributeError> {
        let mut parameter = Parameter {
            idn,
            name: name.into(),
            attribute,
            unit: unit.into(),
            min: None,
            max: None,
            max_len,
            words: Vec::new(),
        };
        parameter.set_value(value)?;
        Ok(parameter)
    }

    /// The parameter as the catalogue describes it, with its default value.
    pub fn from_catalog(info: &IdnInfo) -> Result<Parameter, AttributeError> {
        let value = match info.default {
            CatalogDefault::Number(n) => number_value(info.attribute, i128::from(n)),
            CatalogDefault::Text(text) => Value::Text(text.as_bytes().to_vec()),
            CatalogDefault::IdnList(list) => {
                Value::IdnList(list.iter().map(|&raw| Idn::from_raw(raw)).collect())
            }
        };
        let mut parameter = Parameter::new(
            info.idn,
            info.name,
            info.attribute,
            info.unit,
            info.max_len,
            &value,
        )?;
        parameter.min = info
            .min
            .map(|n| number_value(info.attribute, i128::from(n)));
        parameter.max = info
            .max
            .map(|n| number_value(info.attribute, i128::from(n)));
        Ok(parameter)
    }

    /// Element 7 as service-channel words.
    pub fn words(&self) -> &[u16] {
        &self.words
    }

    /// Element 7 as a typed value.
    pub fn value(&self) -> Result<Value, AttributeError> {
        self.attribute.decode(&self.words)
    }

    /// Element 7 as a number, when it is a single integer.
    pub fn number(&self) -> Option<i128> {
        self.value().ok().and_then(|value| value.as_i128())
    }

    /// Replaces element 7 with `value`, checked against the attribute and `max_len`; no
    /// limit or write-protection check (that is the service channel's job).
    pub fn set_value(&mut self, value: &Value) -> Result<(), AttributeError> {
        if let Some(count) = self.attribute.fixed_words() {
            // Fixed-length data (feedback values, every cycle): encoded into the words held,
            // without a new allocation; same words as `Attribute::encode`.
            let (words, _) = self.attribute.encode_fixed(value)?;
            self.words.clear();
            self.words
                .extend_from_slice(words.get(..count).unwrap_or_default());
            return Ok(());
        }
        let words = self.attribute.encode(value, self.max_len)?;
        self.check_variable_length(&words)?;
        self.words = words;
        Ok(())
    }

    /// Replaces element 7 with already checked words, keeping our own maximum length in the
    /// second word of variable-length data.
    pub(crate) fn set_words(&mut self, words: &[u16]) -> Result<(), AttributeError> {
        self.attribute.decode(words)?;
        self.check_variable_length(words)?;
        let mut stored = words.to_vec();
        if self.attribute.data_length().is_variable() {
            if let Some(maximum) = stored.get_mut(1) {
                *maximum = self.max_len;
            }
        }
        self.words = stored;
        Ok(())
    }

    /// Whether element 7 holds exactly what [`set_value`](Self::set_value) would store for
    /// `Value::Text(bytes)` on variable-length 1-byte data: current length, maximum length
    /// (ours, raised to the current one) and the bytes packed low byte first.
    pub(crate) fn holds_text(&self, bytes: &[u8]) -> bool {
        if self.attribute.data_length() != DataLength::VariableBytes {
            return false;
        }
        let Ok(current) = u16::try_from(bytes.len()) else {
            return false;
        };
        let packed = bytes.chunks(2).map(|pair| {
            u16::from_le_bytes([
                pair.first().copied().unwrap_or(0),
                pair.get(1).copied().unwrap_or(0),
            ])
        });
        match self.words.as_slice() {
            [len, max, data @ ..] => {
                *len == current
                    && *max == self.max_len.max(current)
                    && data.len() == bytes.len().div_ceil(2)
                    && data.iter().copied().eq(packed)
            }
            _ => false,
        }
    }

    fn check_variable_length(&self, words: &[u16]) -> Result<(), AttributeError> {
        if self.attribute.data_length().is_variable() {
            let current = words.first().copied().unwrap_or(0);
            if current > self.max_len {
                return Err(AttributeError::BadVariableLength {
                    current,
                    maximum: self.max_len,
                });
            }
        }
        Ok(())
    }
}

/// The typed value of integer `n` for an attribute: signed for signed decimal, float for
/// floating point, unsigned otherwise (negative numbers stay signed so that encoding rejects
/// them).
pub(crate) fn number_value(attribute: Attribute, n: i128) -> Value {
    use sercos_wire::attribute::DisplayFormat;
    match attribute.display_format() {
        DisplayFormat::SignedDecimal => {
            Value::Signed(n.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64)
        }
        DisplayFormat::Float => Value::Float(n as f64),
        DisplayFormat::Idn if n >= 0 && n <= i128::from(u16::MAX) => {
            Value::Idn(Idn::from_raw(n as u16))
        }
        _ if n < 0 => Value::Signed(n.max(i128::from(i64::MIN)) as i64),
        _ => Value::Unsigned(n.min(i128::from(u64::MAX)) as u64),
    }
}

/// A text as variable-length 1-byte data: current length, maximum length, bytes.
pub(crate) fn text_words(text: &str) -> Vec<u16> {
    let bytes = text.as_bytes();
    let len = u16::try_from(bytes.len()).unwrap_or(0xFFFE);
    let mut words = vec![len, len];
    words.extend(
        bytes
            .chunks(2)
            .take(usize::from(len).div_ceil(2))
            .map(|pair| {
                u16::from_le_bytes([
                    pair.first().copied().unwrap_or(0),
                    pair.get(1).copied().unwrap_or(0),
                ])
            }),
    );
    words
}
