//! Loading an IDN database from a TOML file.
//!
//! ```toml
//! standard = true          # start from the catalogue's IDNs (default true)
//!
//! [[parameter]]            # change a standard IDN's value
//! idn = "S-0-0001"
//! value = 2000
//!
//! [[parameter]]            # or add a manufacturer IDN
//! idn = "P-0-0100"
//! name = "motor temperature"
//! unit = "°C"
//! attribute = 0x7021_0001  # sercos-facts.md attribute layout
//! min = -40
//! max = 200
//! value = 25
//! ```
//!
//! Values are integers (fixed-length numbers, in the units of the last decimal place),
//! floats (floating-point IDNs), strings (text, or an IDN for display format IDN) or arrays
//! (IDN strings for IDN lists, integers for number lists). Errors name the file, the line and
//! column, and the entry.

use std::fmt;
use std::path::{Path, PathBuf};

use sercos_wire::attribute::{Attribute, DataLength, DisplayFormat, Value};
use sercos_wire::idn::Idn;
use sercos_wire::idn_catalog;
use serde::Deserialize;
use toml::Spanned;

use crate::database::IdnDatabase;
use crate::parameter::{Parameter, number_value};

/// Why a configuration file could not be loaded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct ConfigError {
    /// The file.
    pub path: PathBuf,
    /// Line, from 1 (0 when the file could not be read).
    pub line: usize,
    /// Column, from 1 (0 when the file could not be read).
    pub column: usize,
    /// The entry at fault (its IDN text), when known.
    pub entry: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}: ", self.path.display(), self.line, self.column)?;
        if let Some(entry) = &self.entry {
            write!(f, "parameter {entry}: ")?;
        }
        f.write_str(&self.message)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRepr {
    standard: Option<bool>,
    #[serde(default)]
    parameter: Vec<Spanned<EntryRepr>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EntryRepr {
    idn: Spanned<String>,
    name: Option<String>,
    unit: Option<String>,
    attribute: Option<Spanned<i64>>,
    min: Option<Spanned<toml::Value>>,
    max: Option<Spanned<toml::Value>>,
    max_len: Option<Spanned<i64>>,
    value: Option<Spanned<toml::Value>>,
}

/// Reads and parses `path` into a database.
pub fn load(path: &Path) -> Result<IdnDatabase, ConfigError> {
    let text = std::fs::read_to_string(path).map_err(|error| ConfigError {
        path: path.to_path_buf(),
        line: 0,
        column: 0,
        entry: None,
        message: error.to_string(),
    })?;
    parse(&text, path)
}

/// Parses TOML `text` (named `path` in errors) into a database.
pub fn parse(text: &str, path: &Path) -> Result<IdnDatabase, ConfigError> {
    let error_at = |offset: usize, entry: Option<&str>, message: String| {
        let (line, column) = line_column(text, offset);
        ConfigError {
            path: path.to_path_buf(),
            line,
            column,
            entry: entry.map(str::to_string),
            message,
        }
    };
    let file: FileRepr = toml::from_str(text).map_err(|error| {
        let offset = error.span().map(|span| span.start).unwrap_or(0);
        error_at(offset, None, error.message().trim().to_string())
    })?;
    let mut database = if file.standard.unwrap_or(true) {
        IdnDatabase::standard()
    } else {
        IdnDatabase::empty()
    };
    for entry in &file.parameter {
        let entry_text = entry.as_ref().idn.as_ref().as_str();
        build(entry.as_ref(), &database)
            .map(|parameter| database.insert(parameter))
            .map_err(|(offset, message)| {
                error_at(
                    offset.unwrap_or(entry.span().start),
                    Some(entry_text),
                    message,
                )
            })?;
    }
    Ok(database)
}

type EntryError = (Option<usize>, String);

fn build(entry: &EntryRepr, database: &IdnDatabase) -> Result<Parameter, EntryError> {
    let idn: Idn = entry
        .idn
        .as_ref()
        .parse()
        .map_err(|e| (Some(entry.idn.span().start), format!("bad IDN: {e}")))?;
    // Start from what is known: the database so far, then the catalogue.
    let known = database
        .get(idn)
        .cloned()
        .or_else(|| idn_catalog::lookup(idn).and_then(|info| Parameter::from_catalog(info).ok()));
    let attribute = match (&entry.attribute, &known) {
        (Some(raw), _) => Attribute::from_raw(u32::try_from(*raw.as_ref()).map_err(|_| {
            (
                Some(raw.span().start),
                "attribute must be a 32-bit unsigned number".to_string(),
            )
        })?),
        (None, Some(known)) => known.attribute,
        (None, None) => {
            return Err((None, "unknown IDN: give its attribute".to_string()));
        }
    };
    if attribute.data_length() == DataLength::Reserved {
        let at = entry.attribute.as_ref().map(|a| a.span().start);
        return Err((at, "attribute data length 0 is reserved".to_string()));
    }
    let max_len = match (&entry.max_len, &known) {
        (Some(len), _) => u16::try_from(*len.as_ref())
            .ok()
            .filter(|len| *len < u16::MAX)
            .ok_or((
                Some(len.span().start),
                "max_len must be 0-65534".to_string(),
            ))?,
        (None, Some(known)) => known.max_len,
        (None, None) => 64,
    };
    let name = entry
        .name
        .clone()
        .or_else(|| known.as_ref().map(|k| k.name.clone()))
        .unwrap_or_default();
    let unit = entry
        .unit
        .clone()
        .or_else(|| known.as_ref().map(|k| k.unit.clone()))
        .unwrap_or_default();
    let value = match &entry.value {
        Some(value) => value_of(attribute, value)?,
        None => match &known {
            Some(known) if known.attribute == attribute => known
                .value()
                .map_err(|e| (None, format!("default value: {e}")))?,
            _ => default_value(attribute),
        },
    };
    let mut parameter =
        Parameter::new(idn, name, attribute, unit, max_len, &value).map_err(|e| {
            let at = entry.value.as_ref().map(|v| v.span().start);
            (at, format!("value does not fit the attribute: {e}"))
        })?;
    parameter.min = match &entry.min {
        Some(min) => Some(limit_of(attribute, min)?),
        None => known.as_ref().and_then(|k| k.min.clone()),
    };
    parameter.max = match &entry.max {
        Some(max) => Some(limit_of(attribute, max)?),
        None => known.as_ref().and_then(|k| k.max.clone()),
    };
    let number = value.as_f64();
    if let (Some(number), Some(min)) = (number, parameter.min.as_ref().and_then(Value::as_f64)) {
        if number < min {
            return Err((
                entry.value.as_ref().map(|v| v.span().start),
                format!("value below minimum {min}"),
            ));
        }
    }
    if let (Some(number), Some(max)) = (number, parameter.max.as_ref().and_then(Value::as_f64)) {
        if number > max {
            return Err((
                entry.value.as_ref().map(|v| v.span().start),
                format!("value above maximum {max}"),
            ));
        }
    }
    Ok(parameter)
}

fn default_value(attribute: Attribute) -> Value {
    match (
        attribute.data_length().is_variable(),
        attribute.display_format(),
    ) {
        (false, _) => number_value(attribute, 0),
        (true, DisplayFormat::Idn) if attribute.data_length() == DataLength::VariableWords => {
            Value::IdnList(Vec::new())
        }
        (true, DisplayFormat::SignedDecimal) => Value::SignedList(Vec::new()),
        (true, DisplayFormat::Float) => Value::FloatList(Vec::new()),
        (true, _) if attribute.data_length() == DataLength::VariableBytes => {
            Value::Text(Vec::new())
        }
        (true, _) => Value::UnsignedList(Vec::new()),
    }
}

fn limit_of(attribute: Attribute, limit: &Spanned<toml::Value>) -> Result<Value, EntryError> {
    if attribute.data_length().is_variable() {
        return Err((
            Some(limit.span().start),
            "limits apply to fixed-length numbers only".into(),
        ));
    }
    let value = value_of(attribute, limit)?;
    attribute.encode_fixed(&value).map(|_| value).map_err(|e| {
        (
            Some(limit.span().start),
            format!("limit does not fit the attribute: {e}"),
        )
    })
}

fn value_of(attribute: Attribute, value: &Spanned<toml::Value>) -> Result<Value, EntryError> {
    let at = Some(value.span().start);
    let variable = attribute.data_length().is_variable();
    let format = attribute.display_format();
    Ok(match value.as_ref() {
        toml::Value::Integer(n) if !variable => number_value(attribute, i128::from(*n)),
        toml::Value::Float(f) if !variable && format == DisplayFormat::Float => Value::Float(*f),
        toml::Value::String(text) if !variable && format == DisplayFormat::Idn => Value::Idn(
            text.parse()
                .map_err(|e| (at, format!("bad IDN {text:?}: {e}")))?,
        ),
        toml::Value::String(text) if attribute.data_length() == DataLength::VariableBytes => {
            Value::Text(text.as_bytes().to_vec())
        }
        toml::Value::Array(items) if variable => list_of(attribute, items).map_err(|m| (at, m))?,
        other => {
            return Err((
                at,
                format!("a {} does not fit attribute {attribute}", other.type_str()),
            ));
        }
    })
}

fn list_of(attribute: Attribute, items: &[toml::Value]) -> Result<Value, String> {
    let format = attribute.display_format();
    if format == DisplayFormat::Idn && attribute.data_length() == DataLength::VariableWords {
        let idns = items
            .iter()
            .map(|item| match item {
                toml::Value::String(text) => text
                    .parse::<Idn>()
                    .map_err(|e| format!("bad IDN {text:?}: {e}")),
                other => Err(format!("IDN list item is a {}", other.type_str())),
            })
            .collect::<Result<Vec<_>, _>>()?;
        return Ok(Value::IdnList(idns));
    }
    let numbers = items
        .iter()
        .map(|item| match item {
            toml::Value::Integer(n) => Ok(*n),
            other => Err(format!("list item is a {}", other.type_str())),
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(match format {
        DisplayFormat::SignedDecimal => Value::SignedList(numbers),
        DisplayFormat::Float => Value::FloatList(numbers.iter().map(|&n| n as f64).collect()),
        _ if attribute.data_length() == DataLength::VariableBytes => Value::Text(
            numbers
                .iter()
                .map(|&n| u8::try_from(n).map_err(|_| format!("byte {n} out of range")))
                .collect::<Result<Vec<_>, _>>()?,
        ),
        _ => Value::UnsignedList(
            numbers
                .iter()
                .map(|&n| {
                    u64::try_from(n).map_err(|_| format!("negative item {n} in an unsigned list"))
                })
                .collect::<Result<Vec<_>, _>>()?,
        ),
    })
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut end = offset.min(text.len());
    while !text.is_char_boundary(end) {
        end = end.saturating_sub(1);
    }
    let before = text.get(..end).unwrap_or("");
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, column)
}
