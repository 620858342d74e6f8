//! The cyclic data of the MDT and AT records from the telegram type S-0-0015.
//!
//! Standard telegram types 0–6 and their contents (Beckhoff AX2000 manual, IDN 15; AMK ID15):
//!
//! | type | MDT (command values) | AT (feedback values) |
//! |---|---|---|
//! | 0 | none | none |
//! | 1 | torque command S-0-0080 | none |
//! | 2 | velocity command S-0-0036 | velocity feedback S-0-0040 |
//! | 3 | velocity command S-0-0036 | position feedback S-0-0051 |
//! | 4 | position command S-0-0047 | position feedback S-0-0051 |
//! | 5 | position S-0-0047, velocity S-0-0036 | position S-0-0051, velocity S-0-0040 |
//! | 6 | velocity command S-0-0036 | none |
//! | 7 | configured by S-0-0024 | configured by S-0-0016 |
//!
//! sercos-facts.md: S-0-0015 telegram type (0–6 standard, 7 configured by S-0-0016 and
//! S-0-0024). Every record begins with the control word (MDT) or status word (AT) and the
//! service info, two bytes each (sercos-telegrams.md, "Data Record"); the cyclic data follows
//! in list order.

use sercos_wire::attribute::Value;
use sercos_wire::idn::Idn;

use crate::database::IdnDatabase;

/// Bytes of control/status word and service info at the start of every record
/// (sercos-telegrams.md, MDT and AT field tables).
pub const RECORD_HEADER_BYTES: usize = 4;

/// One IDN in the cyclic data of a record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CyclicField {
    /// The IDN carried.
    pub idn: Idn,
    /// Byte offset in the record (from the control or status word).
    pub offset: usize,
    /// Length in bytes (2, 4 or 8).
    pub len: usize,
}

/// The layout of one drive's MDT and AT records.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CyclicLayout {
    /// The cyclic data of the MDT record, in order.
    pub mdt: Vec<CyclicField>,
    /// The cyclic data of the AT record, in order.
    pub at: Vec<CyclicField>,
}

impl CyclicLayout {
    /// Length in bytes of the MDT record: control word, service info and cyclic data.
    pub fn mdt_record_len(&self) -> usize {
        RECORD_HEADER_BYTES + self.mdt.iter().map(|f| f.len).sum::<usize>()
    }

    /// Length in bytes of the AT record: status word, service info and cyclic data.
    pub fn at_record_len(&self) -> usize {
        RECORD_HEADER_BYTES + self.at.iter().map(|f| f.len).sum::<usize>()
    }
}

/// Why the telegram configuration cannot be laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum LayoutError {
    /// S-0-0015 holds a value above 7.
    #[error("telegram type {0} is not 0-7 (S-0-0015)")]
    UnknownTelegramType(i128),
    /// A configuration IDN (S-0-0015, S-0-0016, S-0-0024) is missing or unreadable.
    #[error("{0} is missing or unreadable")]
    ConfigurationMissing(Idn),
    /// A listed IDN is not in the database.
    #[error("{0} in the cyclic data is not present")]
    NotPresent(Idn),
    /// A listed IDN is not in the list of configurable IDNs (S-0-0187 for the AT, S-0-0188
    /// for the MDT).
    #[error("{0} may not be configured in the {1}")]
    NotConfigurable(Idn, &'static str),
    /// A listed IDN has variable-length data and cannot travel cyclically.
    #[error("{0} has variable-length data")]
    NotFixedLength(Idn),
}

/// S-0-0015, S-0-0016, S-0-0024, S-0-0187, S-0-0188 (sercos-facts.md, timing parameters).
const TELEGRAM_TYPE: Idn = Idn::from_raw(15);
const AT_LIST: Idn = Idn::from_raw(16);
const MDT_LIST: Idn = Idn::from_raw(24);
const AT_CONFIGURABLE: Idn = Idn::from_raw(187);
const MDT_CONFIGURABLE: Idn = Idn::from_raw(188);

/// Computes the cyclic layout from the database's S-0-0015 (and S-0-0016, S-0-0024 for
/// type 7).
pub fn layout(database: &IdnDatabase) -> Result<CyclicLayout, LayoutError> {
    let telegram_type = database
        .number(TELEGRAM_TYPE)
        .ok_or(LayoutError::ConfigurationMissing(TELEGRAM_TYPE))?;
    // Standard telegram types 0–6 (module table): the master's table, so drive and master
    // cannot disagree on what a type carries.
    let (mdt, at) = match u16::try_from(telegram_type)
        .ok()
        .and_then(sercdrv::master::standard_telegram)
    {
        Some(lists) => lists,
        None if telegram_type == 7 => {
            let mdt = idn_list(database, MDT_LIST)?;
            let at = idn_list(database, AT_LIST)?;
            // Beckhoff AX2000, IDN 15: the IDNs allowed in the AT and MDT are listed in
            // IDN 187 and IDN 188.
            check_configurable(database, &mdt, MDT_CONFIGURABLE, "MDT")?;
            check_configurable(database, &at, AT_CONFIGURABLE, "AT")?;
            (mdt, at)
        }
        None => return Err(LayoutError::UnknownTelegramType(telegram_type)),
    };
    Ok(CyclicLayout {
        mdt: fields(database, &mdt)?,
        at: fields(database, &at)?,
    })
}

fn idn_list(database: &IdnDatabase, list: Idn) -> Result<Vec<Idn>, LayoutError> {
    match database.get(list).and_then(|p| p.value().ok()) {
        Some(Value::IdnList(idns)) => Ok(idns),
        _ => Err(LayoutError::ConfigurationMissing(list)),
    }
}

fn check_configurable(
    database: &IdnDatabase,
    idns: &[Idn],
    allowed: Idn,
    telegram: &'static str,
) -> Result<(), LayoutError> {
    let allowed = idn_list(database, allowed)?;
    match idns.iter().find(|idn| !allowed.contains(idn)) {
        Some(&idn) => Err(LayoutError::NotConfigurable(idn, telegram)),
        None => Ok(()),
    }
}

fn fields(database: &IdnDatabase, idns: &[Idn]) -> Result<Vec<CyclicField>, LayoutError> {
    let mut offset = RECORD_HEADER_BYTES;
    let mut out = Vec::with_capacity(idns.len());
    for &idn in idns {
        let parameter = database.get(idn).ok_or(LayoutError::NotPresent(idn))?;
        let words = parameter
            .attribute
            .fixed_words()
            .ok_or(LayoutError::NotFixedLength(idn))?;
        out.push(CyclicField {
            idn,
            offset,
            len: words * 2,
        });
        offset += words * 2;
    }
    Ok(out)
}
