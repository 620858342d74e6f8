//! Operation data from the text a person types, read by the IDN's attribute: decimal places,
//! sign, hexadecimal, binary, text, IDNs and lists (sercos-facts.md, IDNs, "Attribute (32
//! bit)": bits 22–20 type/display, bits 27–24 decimal places, bits 18–16 data length).
//!
//! The value is parsed into a [`Value`] and encoded into service-channel words by
//! [`Attribute::encode`]; readings chosen: `docs/spec-notes.md`, "IDN tool".

use sercos_wire::attribute::{Attribute, AttributeError, DataLength, DisplayFormat, Value};
use sercos_wire::idn::Idn;

/// Why a text is not a value of an attribute.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ValueParseError {
    /// The text is not a number of the attribute's kind.
    #[error("{text:?} is not {expected}")]
    NotANumber {
        /// The offending text (one list element for lists).
        text: String,
        /// What was expected, e.g. "a signed decimal number with up to 4 decimal places".
        expected: String,
    },
    /// More decimal places than the attribute has (sercos-facts.md, bits 27–24).
    #[error("{text:?} has more than {places} decimal places")]
    TooManyPlaces {
        /// The text.
        text: String,
        /// The attribute's decimal places.
        places: u8,
    },
    /// The number is not a whole multiple of the conversion factor (bits 15–0).
    #[error("{text:?} is not a multiple of the conversion factor {factor}")]
    NotAMultiple {
        /// The text.
        text: String,
        /// The factor.
        factor: u16,
    },
    /// The attribute cannot carry the value (range, type, reserved length).
    #[error("{text:?} does not fit the attribute ({source})")]
    DoesNotFit {
        /// The text.
        text: String,
        /// Why.
        source: AttributeError,
    },
}

/// Parses `text` as operation data of `attribute` and encodes it into the words written to
/// element 7 (variable-length data with its current and maximum length, sercos-facts.md,
/// "Variable-length data").
pub fn parse_words(attribute: Attribute, text: &str) -> Result<Vec<u16>, ValueParseError> {
    let value = parse_value(attribute, text)?;
    attribute
        .encode(&value, 0)
        .map_err(|source| ValueParseError::DoesNotFit {
            text: text.to_string(),
            source,
        })
}

/// Parses `text` as a [`Value`] of `attribute`.
pub fn parse_value(attribute: Attribute, text: &str) -> Result<Value, ValueParseError> {
    let length = attribute.data_length();
    let format = attribute.display_format();
    if length == DataLength::Reserved {
        return Err(ValueParseError::DoesNotFit {
            text: text.to_string(),
            source: AttributeError::ReservedLength,
        });
    }
    if !length.is_variable() {
        return parse_scalar(attribute, text.trim());
    }
    // sercos-facts.md: data length 4 = a variable list of 1-byte elements (text).
    if length == DataLength::VariableBytes {
        return Ok(Value::Text(text.as_bytes().to_vec()));
    }
    let items = list_items(text);
    match (format, length) {
        (DisplayFormat::Idn, DataLength::VariableWords) => items
            .iter()
            .map(|item| parse_idn(item))
            .collect::<Result<Vec<_>, _>>()
            .map(Value::IdnList),
        (DisplayFormat::Float, _) => items
            .iter()
            .map(|item| parse_float(item))
            .collect::<Result<Vec<_>, _>>()
            .map(Value::FloatList),
        (DisplayFormat::SignedDecimal, _) => items
            .iter()
            .map(|item| {
                scaled_integer(attribute, item)
                    .and_then(|v| i64::try_from(v).map_err(|_| out_of_range(item)))
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Value::SignedList),
        _ => items
            .iter()
            .map(|item| {
                scaled_integer(attribute, item)
                    .and_then(|v| u64::try_from(v).map_err(|_| out_of_range(item)))
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Value::UnsignedList),
    }
}

/// The elements of a list written `[a, b]`, `[a b]` or `a,b` (brackets optional; `[]` is
/// empty).
fn list_items(text: &str) -> Vec<String> {
    let inner = text.trim();
    let inner = inner.strip_prefix('[').unwrap_or(inner);
    let inner = inner.strip_suffix(']').unwrap_or(inner);
    inner
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

fn out_of_range(text: &str) -> ValueParseError {
    ValueParseError::DoesNotFit {
        text: text.to_string(),
        source: AttributeError::OutOfRange,
    }
}

/// One fixed-length value.
fn parse_scalar(attribute: Attribute, text: &str) -> Result<Value, ValueParseError> {
    match attribute.display_format() {
        DisplayFormat::Float => parse_float(text).map(Value::Float),
        // sercos-facts.md: display format 5, an IDN (2 bytes).
        DisplayFormat::Idn if attribute.data_length() == DataLength::TwoBytes => {
            parse_idn(text).map(Value::Idn)
        }
        DisplayFormat::SignedDecimal => {
            let v = scaled_integer(attribute, text)?;
            i64::try_from(v)
                .map(Value::Signed)
                .map_err(|_| out_of_range(text))
        }
        _ => {
            let v = scaled_integer(attribute, text)?;
            u64::try_from(v)
                .map(Value::Unsigned)
                .map_err(|_| out_of_range(text))
        }
    }
}

fn parse_idn(text: &str) -> Result<Idn, ValueParseError> {
    text.parse::<Idn>()
        .map_err(|e| ValueParseError::NotANumber {
            text: text.to_string(),
            expected: format!("an IDN such as S-0-0011 ({e})"),
        })
}

fn parse_float(text: &str) -> Result<f64, ValueParseError> {
    text.parse::<f64>()
        .ok()
        .filter(|f| f.is_finite())
        .ok_or_else(|| ValueParseError::NotANumber {
            text: text.to_string(),
            expected: "a floating-point number".into(),
        })
}

/// A raw integer of the attribute from `text`: `0x…`/`…H` (hexadecimal) and `0b…` (binary)
/// are raw bits; decimal text is scaled by the decimal places and divided by the conversion
/// factor, the inverse of what the display does (docs/spec-notes.md, "IDN attributes").
fn scaled_integer(attribute: Attribute, text: &str) -> Result<i128, ValueParseError> {
    let clean: String = text.chars().filter(|&c| c != '_').collect();
    if let Some(raw) = raw_bits(&clean) {
        return raw.ok_or_else(|| ValueParseError::NotANumber {
            text: text.to_string(),
            expected: "a hexadecimal or binary number".into(),
        });
    }
    let format = attribute.display_format();
    let signed = format == DisplayFormat::SignedDecimal;
    let decimal = matches!(
        format,
        DisplayFormat::SignedDecimal | DisplayFormat::UnsignedDecimal
    );
    // Binary and hexadecimal formats show no decimal places and no factor.
    let places = if decimal {
        attribute.decimal_places()
    } else {
        0
    };
    let expected = || {
        let kind = if signed {
            "a signed decimal number"
        } else {
            "an unsigned decimal number"
        };
        let kind = if decimal {
            kind.to_string()
        } else {
            "a number (decimal, 0x… hexadecimal or 0b… binary)".to_string()
        };
        match places {
            0 => kind,
            p => format!("{kind} with up to {p} decimal places"),
        }
    };
    let not_a_number = || ValueParseError::NotANumber {
        text: text.to_string(),
        expected: expected(),
    };
    let (negative, digits) = match clean.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, clean.strip_prefix('+').unwrap_or(&clean)),
    };
    if negative && !signed {
        return Err(not_a_number());
    }
    let (whole, fraction) = digits.split_once('.').unwrap_or((digits, ""));
    let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    if (whole.is_empty() && fraction.is_empty()) || !all_digits(whole) || !all_digits(fraction) {
        return Err(not_a_number());
    }
    let kept = fraction.len().min(usize::from(places));
    let (fraction, dropped) = fraction.split_at(kept);
    if dropped.bytes().any(|b| b != b'0') {
        return Err(ValueParseError::TooManyPlaces {
            text: text.to_string(),
            places,
        });
    }
    // At most 38 digits fit an i128; longer numbers are out of range for every attribute.
    let padded = format!("{whole}{fraction:0<width$}", width = usize::from(places));
    let padded = padded.trim_start_matches('0');
    let magnitude: i128 = if padded.is_empty() {
        0
    } else if padded.len() > 38 {
        return Err(out_of_range(text));
    } else {
        padded.parse().map_err(|_| out_of_range(text))?
    };
    let factor = attribute.conversion_factor();
    let magnitude = if decimal && factor > 1 {
        let f = i128::from(factor);
        if magnitude % f != 0 {
            return Err(ValueParseError::NotAMultiple {
                text: text.to_string(),
                factor,
            });
        }
        magnitude / f
    } else {
        magnitude
    };
    Ok(if negative { -magnitude } else { magnitude })
}

/// `Some(Some(bits))` for `0x1F`, `1FH`, `0b101`; `Some(None)` for a malformed one; `None`
/// when the text is not written in hexadecimal or binary.
fn raw_bits(text: &str) -> Option<Option<i128>> {
    let lower = text.to_ascii_lowercase();
    let (digits, radix) = if let Some(d) = lower.strip_prefix("0x") {
        (d, 16)
    } else if let Some(d) = lower.strip_prefix("0b") {
        (d, 2)
    } else if let Some(d) = lower.strip_suffix('h') {
        // The documents' own notation for codes and words: 7007H.
        (d, 16)
    } else {
        return None;
    };
    // 8-byte data shows 64 binary digits; a number beyond 128 bits fails below (overflow).
    if digits.is_empty() {
        return Some(None);
    }
    Some(
        u128::from_str_radix(digits, radix)
            .ok()
            .and_then(|v| i128::try_from(v).ok()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn attr(length: DataLength, format: DisplayFormat, places: u8) -> Attribute {
        Attribute::new(length, format).with_decimal_places(places)
    }

    // sercos-facts.md, attribute bits 27-24: decimal places scale the written number.
    #[test]
    fn decimals_are_scaled_exactly() {
        let a = attr(DataLength::FourBytes, DisplayFormat::SignedDecimal, 4);
        assert_eq!(parse_value(a, "1500.0").unwrap(), Value::Signed(15_000_000));
        assert_eq!(parse_value(a, "-0.0001").unwrap(), Value::Signed(-1));
        assert_eq!(parse_value(a, "12").unwrap(), Value::Signed(120_000));
        assert_eq!(parse_value(a, "1.50000").unwrap(), Value::Signed(15_000));
        assert!(matches!(
            parse_value(a, "1.00005"),
            Err(ValueParseError::TooManyPlaces { places: 4, .. })
        ));
        assert!(parse_value(a, "1.2.3").is_err());
        assert!(parse_value(a, "abc").is_err());
        assert!(parse_value(a, "").is_err());
        assert!(parse_value(a, ".").is_err());
    }

    // sercos-facts.md, display format 1 unsigned: no sign.
    #[test]
    fn unsigned_refuses_a_sign_and_range_is_checked() {
        let a = attr(DataLength::TwoBytes, DisplayFormat::UnsignedDecimal, 0);
        assert!(parse_words(a, "-1").is_err());
        assert_eq!(parse_words(a, "65535").unwrap(), vec![0xFFFF]);
        assert!(matches!(
            parse_words(a, "65536"),
            Err(ValueParseError::DoesNotFit { .. })
        ));
        assert!(parse_words(a, "99999999999999999999999999999999999999999").is_err());
    }

    // sercos-facts.md, display formats 0 binary and 3 hexadecimal.
    #[test]
    fn hex_and_binary_are_raw_bits() {
        let a = attr(DataLength::TwoBytes, DisplayFormat::Binary, 0);
        assert_eq!(parse_words(a, "0b0000000000000010").unwrap(), vec![2]);
        assert_eq!(parse_words(a, "0x8001").unwrap(), vec![0x8001]);
        assert_eq!(parse_words(a, "7007H").unwrap(), vec![0x7007]);
        assert_eq!(parse_words(a, "5").unwrap(), vec![5]);
        assert!(parse_words(a, "0xZZ").is_err());
        // Hex ignores decimal places on decimal formats too: raw bits.
        let d = attr(DataLength::FourBytes, DisplayFormat::SignedDecimal, 4);
        assert_eq!(parse_words(d, "0x10").unwrap(), vec![0x10, 0]);
    }

    // sercos-facts.md: 4-byte values travel low word first.
    #[test]
    fn four_byte_words_low_first() {
        let a = attr(DataLength::FourBytes, DisplayFormat::SignedDecimal, 4);
        assert_eq!(parse_words(a, "-0.0001").unwrap(), vec![0xFFFF, 0xFFFF]);
        assert_eq!(parse_words(a, "6.5536").unwrap(), vec![0, 1]);
    }

    // sercos-facts.md, "Variable-length data": current length, maximum length, data.
    #[test]
    fn idn_lists_and_text() {
        let a = attr(DataLength::VariableWords, DisplayFormat::Idn, 0);
        assert_eq!(
            parse_words(a, "[S-0-0011,S-0-0051]").unwrap(),
            vec![4, 4, 11, 51]
        );
        assert_eq!(
            parse_words(a, "S-0-0011, P-0-0019").unwrap(),
            vec![4, 4, 11, 0x8013]
        );
        assert_eq!(parse_words(a, "[]").unwrap(), vec![0, 0]);
        assert!(parse_words(a, "[S-0-0011,X-1]").is_err());
        let t = attr(DataLength::VariableBytes, DisplayFormat::Text, 0);
        assert_eq!(parse_words(t, "abc").unwrap(), vec![3, 3, 0x6261, 0x0063]);
        let l = attr(DataLength::VariableLongs, DisplayFormat::SignedDecimal, 1);
        assert_eq!(
            parse_value(l, "[1.5, -2]").unwrap(),
            Value::SignedList(vec![15, -20])
        );
    }

    // sercos-facts.md, display format 6 floating point; format 5 IDN.
    #[test]
    fn floats_and_single_idns() {
        let f = attr(DataLength::FourBytes, DisplayFormat::Float, 0);
        assert_eq!(parse_value(f, "1.25").unwrap(), Value::Float(1.25));
        assert!(parse_value(f, "NaN").is_err());
        let i = attr(DataLength::TwoBytes, DisplayFormat::Idn, 0);
        assert_eq!(
            parse_value(i, "S-0-0036").unwrap(),
            Value::Idn(Idn::from_raw(36))
        );
    }

    // docs/spec-notes.md "IDN attributes": a factor above 1 multiplies for display, so
    // the written number is divided by it.
    #[test]
    fn conversion_factor_divides() {
        let a = attr(DataLength::TwoBytes, DisplayFormat::UnsignedDecimal, 0)
            .with_conversion_factor(10);
        assert_eq!(parse_words(a, "250").unwrap(), vec![25]);
        assert!(matches!(
            parse_words(a, "255"),
            Err(ValueParseError::NotAMultiple { factor: 10, .. })
        ));
    }

    fn fixed_attribute() -> impl Strategy<Value = Attribute> {
        (
            prop_oneof![
                Just(DataLength::TwoBytes),
                Just(DataLength::FourBytes),
                Just(DataLength::EightBytes)
            ],
            prop_oneof![
                Just(DisplayFormat::Binary),
                Just(DisplayFormat::UnsignedDecimal),
                Just(DisplayFormat::SignedDecimal),
                Just(DisplayFormat::Hexadecimal)
            ],
            0u8..=9,
        )
            .prop_map(|(l, f, p)| attr(l, f, p))
    }

    proptest! {
        // Nothing a person types panics the parser, whatever the attribute.
        #[test]
        fn any_text_any_attribute_never_panics(raw in any::<u32>(), text in ".{0,48}") {
            let _ = parse_words(Attribute::from_raw(raw), &text);
        }

        // sercos-facts.md, attribute bits 27-24 and 22-20: what the tool shows for a value
        // parses back to the same words (fixed-length numbers, factor 1).
        #[test]
        fn shown_values_parse_back(a in fixed_attribute(), words in proptest::collection::vec(any::<u16>(), 4)) {
            let n = a.fixed_words().unwrap_or(1);
            let words = &words[..n];
            let value = a.decode(words).expect("fixed words decode");
            let shown = a.display(&value).to_string();
            prop_assert_eq!(parse_words(a, &shown).expect(&shown), words.to_vec());
        }

        // sercos-facts.md, "Variable-length data": IDN lists as shown parse back.
        #[test]
        fn shown_idn_lists_parse_back(raw in proptest::collection::vec(any::<u16>(), 0..12)) {
            let a = attr(DataLength::VariableWords, DisplayFormat::Idn, 0);
            let value = Value::IdnList(raw.iter().map(|&r| Idn::from_raw(r)).collect());
            let shown = a.display(&value).to_string();
            let words = parse_words(a, &shown).expect(&shown);
            prop_assert_eq!(a.decode(&words).expect("decodes"), value);
        }
    }

    #[test]
    fn reserved_length_is_refused() {
        let a = Attribute::from_raw(0);
        assert!(parse_words(a, "1").is_err());
    }
}
