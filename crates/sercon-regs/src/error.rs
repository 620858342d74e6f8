//! Typed errors of this crate.

use crate::ram::header::HeaderKind;

/// A value does not fit a register or RAM field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("value {value} does not fit field {field} ({width} bits)")]
pub struct FieldError {
    /// The datasheet name of the field.
    pub field: &'static str,
    /// The rejected value.
    pub value: u16,
    /// The field's width in bits on the variant in use.
    pub width: u8,
}

impl FieldError {
    /// Checks that `value` fits `width` bits, naming the field in the error.
    pub(crate) const fn check(field: &'static str, value: u16, width: u8) -> Result<u16, Self> {
        if width < 16 && value >> width != 0 {
            Err(FieldError {
                field,
                value,
                width,
            })
        } else {
            Ok(value)
        }
    }
}

/// A RAM structure could not be decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum RamError {
    /// Word 0 carries the marker bits 10 (bit 15 = 1, bit 14 = 0), which no structure
    /// uses (ERRATA "telegram header marker bits").
    #[error("word 0 = {word0:#06x}: marker bits 10 are invalid")]
    InvalidMarker {
        /// The offending word 0.
        word0: u16,
    },
    /// Word 0 marks another kind of structure than the one asked for.
    #[error("expected a {expected:?}, word 0 marks a {found:?}")]
    WrongKind {
        /// The structure asked for.
        expected: HeaderKind,
        /// The structure word 0 marks.
        found: HeaderKind,
    },
    /// Fewer words were given than the structure has.
    #[error("structure needs {needed} words, {got} given")]
    TooShort {
        /// Words the structure has.
        needed: usize,
        /// Words given.
        got: usize,
    },
}
