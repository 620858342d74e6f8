//! Procedure commands: S-0-0099 reset class 1 diagnostic, S-0-0127 and S-0-0128 transition
//! checks.
//!
//! sercos-facts.md, "Procedure commands": the master writes 3 (set and enable) to element 7
//! to start one and 0 to cancel or acknowledge it. The relations checked by S-0-0127 are
//! sercos-facts.md, "Timing parameters": t1min ≤ t1 < t2 − tATMT; t4 ≤ tScyc − t5;
//! t2 + MDT duration + S-0-0090 < t3 ≤ tScyc.

use sercos_wire::attribute::Value;
use sercos_wire::idn::Idn;
use sercos_wire::telegram::CommunicationPhase;

use crate::database::IdnDatabase;
use crate::telegram_layout;

/// S-0-0099, reset class 1 diagnostic.
pub const RESET_CLASS_1_DIAGNOSTIC: Idn = Idn::from_raw(99);
/// S-0-0127, communication phase 3 transition check.
pub const PHASE_3_TRANSITION_CHECK: Idn = Idn::from_raw(127);
/// S-0-0128, communication phase 4 transition check.
pub const PHASE_4_TRANSITION_CHECK: Idn = Idn::from_raw(128);
/// S-0-0011, class 1 diagnostic.
pub const CLASS_1_DIAGNOSTIC: Idn = Idn::from_raw(11);
/// P-0-0003, simulated fault of the emulated drive (1 = fault present).
pub const SIMULATED_FAULT: Idn = Idn::from_raw(0x8003);
/// P-0-0002, bit rate in Mbit/s (the line's rate is set by a switch, not by an IDN).
pub const BIT_RATE: Idn = Idn::from_raw(0x8002);

/// The IDNs S-0-0127 reads: the standard ones every slave knows
/// ([`sercdrv::slave::PHASE_3_CHECKED`]: timing S-0-0001…-0010, -0089, -0090, telegram
/// configuration S-0-0015, -0016, -0024) and this drive's bit rate. A write of one of them
/// after the check makes the drive forget that it passed (docs/spec-notes.md, "Driver slave
/// and drive node": a check passed is remembered until a parameter it checked changes).
pub const PHASE_3_CHECKED: [Idn; 16] = with_bit_rate(sercdrv::slave::PHASE_3_CHECKED);

/// The IDNs S-0-0128 reads: the primary operation mode S-0-0032 and the telegram
/// configuration (S-0-0015, -0016, -0024).
pub const PHASE_4_CHECKED: [Idn; 4] = sercdrv::slave::PHASE_4_CHECKED;

/// `standard` followed by [`BIT_RATE`].
const fn with_bit_rate(standard: [Idn; 15]) -> [Idn; 16] {
    let mut all = [BIT_RATE; 16];
    let mut i = 0;
    while i < standard.len() {
        all[i] = standard[i];
        i += 1;
    }
    all
}

/// The parameters transition check `check` reads (empty for other commands).
pub fn checked_by(check: Idn) -> &'static [Idn] {
    match check {
        PHASE_3_TRANSITION_CHECK => &PHASE_3_CHECKED,
        PHASE_4_TRANSITION_CHECK => &PHASE_4_CHECKED,
        _ => &[],
    }
}

/// The status of a procedure command, readable as its operation data.
///
/// docs/spec-notes.md, "Emulated drive": bit 0 set, bit 1 enabled, bit 2 executed, bit 3
/// error. The emulated drive runs a command at once, so "in progress" is never observed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CommandStatus {
    /// 0000H: not set (never set, or cancelled with 0).
    NotSet,
    /// 0003H: set and enabled, still running.
    InProgress,
    /// 0007H: set, enabled and executed correctly.
    Executed,
    /// 000BH: set and enabled, but it failed (the reason is in S-0-0095).
    Error,
}

impl CommandStatus {
    /// The status word.
    pub const fn bits(self) -> u16 {
        match self {
            CommandStatus::NotSet => 0x0000,
            CommandStatus::InProgress => 0x0003,
            CommandStatus::Executed => 0x0007,
            CommandStatus::Error => 0x000B,
        }
    }
}

/// Runs procedure command `idn` on the database; `Err` holds the diagnostic message.
pub(crate) fn execute(database: &mut IdnDatabase, idn: Idn) -> Result<(), String> {
    match idn {
        RESET_CLASS_1_DIAGNOSTIC => reset_class_1(database),
        PHASE_3_TRANSITION_CHECK => phase_3_check(database),
        PHASE_4_TRANSITION_CHECK => phase_4_check(database),
        // Procedure commands of a configuration file have no behaviour: they succeed.
        _ => Ok(()),
    }
}

fn reset_class_1(database: &mut IdnDatabase) -> Result<(), String> {
    if database.number(SIMULATED_FAULT).unwrap_or(0) != 0 {
        return Err("S-0-0099: the fault is still present (P-0-0003)".into());
    }
    database
        .set_internal(CLASS_1_DIAGNOSTIC, &Value::Unsigned(0))
        .map_err(|e| format!("S-0-0099: {e}"))?;
    database.set_diagnostic_message("");
    Ok(())
}

/// Reads a timing or configuration IDN as a number.
fn get(database: &IdnDatabase, raw: u16) -> Result<i128, String> {
    let idn = Idn::from_raw(raw);
    database
        .number(idn)
        .ok_or_else(|| format!("S-0-0127: {idn} is missing"))
}

/// The nominal duration in µs of an MDT with `data_bytes` of data at `mbit` Mbit/s: two
/// flags, address, data and FCS, without inserted zeros (docs/spec-notes.md, "Emulated
/// drive").
pub fn mdt_duration_us(data_bytes: i128, mbit: i128) -> i128 {
    let bits = (data_bytes + 5) * 8;
    if mbit <= 0 {
        return i128::MAX / 4;
    }
    (bits + mbit - 1) / mbit
}

fn phase_3_check(database: &mut IdnDatabase) -> Result<(), String> {
    if database.phase() != CommunicationPhase::Phase2 {
        return Err("S-0-0127: only in phase 2".into());
    }
    let nc_cycle = get(database, 1)?;
    let t_scyc = get(database, 2)?;
    let t1min = get(database, 3)?;
    let t_atmt = get(database, 4)?;
    let t5 = get(database, 5)?;
    let t1 = get(database, 6)?;
    let t4 = get(database, 7)?;
    let t3 = get(database, 8)?;
    let mdt_position = get(database, 9)?;
    let mdt_length = get(database, 10)?;
    let t2 = get(database, 89)?;
    let copy_time = get(database, 90)?;
    let mbit = database.number(BIT_RATE).unwrap_or(2);
    let layout = telegram_layout::layout(database).map_err(|e| format!("S-0-0127: {e}"))?;

    if t_scyc <= 0 || nc_cycle <= 0 || nc_cycle % t_scyc != 0 {
        // docs/spec-notes.md: the NC cycle is a whole multiple of the communication cycle.
        return Err(format!(
            "S-0-0127: NC cycle time {nc_cycle} µs is not a multiple of tScyc {t_scyc} µs"
        ));
    }
    // sercos-facts.md: t1min ≤ t1 < t2 − tATMT.
    if t1 < t1min || t1 >= t2 - t_atmt {
        return Err(format!(
            "S-0-0127: t1 = {t1} µs outside [t1min {t1min}, t2 {t2} - tATMT {t_atmt})"
        ));
    }
    // sercos-facts.md: t4 ≤ tScyc − t5.
    if t4 > t_scyc - t5 {
        return Err(format!("S-0-0127: t4 = {t4} µs > tScyc {t_scyc} - t5 {t5}"));
    }
    // sercos-facts.md: t2 + MDT duration + S-0-0090 < t3 ≤ tScyc.
    let mdt = mdt_duration_us(mdt_length, mbit);
    if t2 + mdt + copy_time >= t3 || t3 > t_scyc {
        return Err(format!(
            "S-0-0127: t3 = {t3} µs outside (t2 {t2} + MDT {mdt} + {copy_time}, tScyc {t_scyc}]"
        ));
    }
    // sercos-facts.md: the drive's record sits at byte offset S-0-0009 from the address
    // field, inside the S-0-0010 bytes of MDT data.
    let record = i128::try_from(layout.mdt_record_len()).unwrap_or(i128::MAX / 4);
    if mdt_position < 1 || mdt_position - 1 + record > mdt_length {
        return Err(format!(
            "S-0-0127: MDT record of {record} bytes at {mdt_position} does not fit {mdt_length} bytes"
        ));
    }
    Ok(())
}

fn phase_4_check(database: &mut IdnDatabase) -> Result<(), String> {
    if database.phase() != CommunicationPhase::Phase3 {
        return Err("S-0-0128: only in phase 3".into());
    }
    if database.number(CLASS_1_DIAGNOSTIC).unwrap_or(0) != 0 {
        return Err("S-0-0128: class 1 diagnostic pending".into());
    }
    let mode = database.number(Idn::from_raw(32)).unwrap_or(0);
    if crate::motion::ControlMode::from_operation_mode(mode).is_none() {
        return Err(format!(
            "S-0-0128: primary operation mode {mode:#06X} not supported"
        ));
    }
    telegram_layout::layout(database)
        .map(|_| ())
        .map_err(|e| format!("S-0-0128: {e}"))
}
