//! The slave's cycle from its own IDN store: the values the master wrote in phase 2
//! (S-0-0002, S-0-0006, S-0-0009, S-0-0010, S-0-0089) and the device's cyclic data lengths,
//! turned into the [`CycleTiming`] that [`ram_layout::build`](crate::ram_layout::build) lays
//! out for `Role::Slave`.

use sercos_wire::idn::{Element, Idn};
use sercos_wire::time::BitRate;

use super::config::SlaveConfig;
use super::device::CyclicLengths;
use super::error::SlaveError;
use crate::idn_store::IdnStore;
use crate::timing::{
    self, CycleTiming, DriveParameters, DrivePlan, MAX_CYCLE_US, MAX_RECORD_WORDS, MIN_CYCLE_US,
    MST_BYTES, NonCyclicPlan, RECORD_HEADER_BYTES, TelegramSlot, TimingRequest, TimingRules,
};

/// S-0-0002, communication cycle time tScyc (sercos-facts.md, timing parameters).
pub const CYCLE_TIME: Idn = Idn::from_raw(2);
/// S-0-0006, AT transmission starting time t1.
pub const AT_START: Idn = Idn::from_raw(6);
/// S-0-0009, position of the drive's record in the MDT.
pub const MDT_POSITION: Idn = Idn::from_raw(9);
/// S-0-0010, length of the MDT data.
pub const MDT_LENGTH: Idn = Idn::from_raw(10);
/// S-0-0089, MDT transmission starting time t2.
pub const MDT_START: Idn = Idn::from_raw(89);
/// S-0-0127, phase 3 transition check (procedure command).
pub const PHASE_3_CHECK: Idn = Idn::from_raw(127);
/// S-0-0128, phase 4 transition check (procedure command).
pub const PHASE_4_CHECK: Idn = Idn::from_raw(128);

/// Procedure command status "executed correctly": bits 0 set, 1 enabled, 2 executed, no
/// error bit 3 (spec-notes "IDN attributes ... emulated drive": 0007H).
const COMMAND_EXECUTED: u16 = 0x0007;

/// The standard parameters S-0-0127 reads: the timing S-0-0001…-0010, -0089, -0090 and the
/// telegram configuration S-0-0015/-0016/-0024 (sercos-facts.md, timing parameters).
pub const PHASE_3_CHECKED: [Idn; 15] = [
    Idn::from_raw(1),
    Idn::from_raw(2),
    Idn::from_raw(3),
    Idn::from_raw(4),
    Idn::from_raw(5),
    Idn::from_raw(6),
    Idn::from_raw(7),
    Idn::from_raw(8),
    Idn::from_raw(9),
    Idn::from_raw(10),
    Idn::from_raw(15),
    Idn::from_raw(16),
    Idn::from_raw(24),
    Idn::from_raw(89),
    Idn::from_raw(90),
];

/// The standard parameters S-0-0128 reads: the primary operation mode S-0-0032 and the
/// telegram configuration S-0-0015/-0016/-0024.
pub const PHASE_4_CHECKED: [Idn; 4] = [
    Idn::from_raw(32),
    Idn::from_raw(15),
    Idn::from_raw(16),
    Idn::from_raw(24),
];

/// The parameters transition check `check` reads ([`PHASE_3_CHECKED`], [`PHASE_4_CHECKED`]),
/// empty for other commands. A write of one of them after the check passed makes the slave
/// forget the pass (docs/spec-notes.md, "Driver slave and drive node").
pub fn checked_by(check: Idn) -> &'static [Idn] {
    match check {
        PHASE_3_CHECK => &PHASE_3_CHECKED,
        PHASE_4_CHECK => &PHASE_4_CHECKED,
        _ => &[],
    }
}

/// The status word of procedure command `idn` (element 7), if the store has it.
pub fn command_status<S: IdnStore + ?Sized>(store: &S, idn: Idn) -> Option<u16> {
    // sercos-facts.md "Procedure commands"; reading element 7 gives the command status.
    store
        .read_element(idn, Element::OperationData)
        .ok()
        .and_then(|w| w.first().copied())
}

/// Whether procedure command `idn` has been executed correctly (element 7 reads 0007H).
pub fn command_executed<S: IdnStore + ?Sized>(store: &S, idn: Idn) -> bool {
    // sercos-facts.md "Procedure commands"; reading element 7 gives the command status.
    store
        .read_element(idn, Element::OperationData)
        .is_ok_and(|w| w.first().copied() == Some(COMMAND_EXECUTED))
}

/// The operation data of a 2- or 4-byte IDN as an unsigned number (low word first,
/// sercos-telegrams.md / ERRATA "multi-byte fields").
pub fn read_number<S: IdnStore + ?Sized>(store: &S, idn: Idn) -> Result<u32, SlaveError> {
    let words = store
        .read_element(idn, Element::OperationData)
        .map_err(|_| SlaveError::ParameterMissing(idn))?;
    match words.as_slice() {
        [low] => Ok(u32::from(*low)),
        [low, high, ..] => Ok(u32::from(*low) | (u32::from(*high) << 16)),
        [] => Err(SlaveError::ParameterMissing(idn)),
    }
}

fn slot(start_us: u32, bytes: u32, rate: BitRate) -> TelegramSlot {
    TelegramSlot {
        start_us,
        duration_us: u32::try_from(timing::worst_case_micros(u64::from(bytes), rate))
            .unwrap_or(u32::MAX),
        bytes,
    }
}

/// The phase 0–2 slots, planned as the master plans them (`timing::plan_cycle`'s
/// `noncyclic`: AT right after the MST and the gap, MDT at half the cycle) for the
/// configured phase 0–2 cycle.
pub fn noncyclic_plan(config: &SlaveConfig) -> Result<NonCyclicPlan, SlaveError> {
    let request = TimingRequest {
        bit_rate: config.bit_rate,
        cycle_time_us: config.noncyclic_cycle_us,
        nc_cycle_time_us: config.noncyclic_cycle_us,
        drives: vec![DriveParameters {
            address: config.address,
            t1min_us: 0,
            t_atmt_us: 0,
            t5_us: 0,
            t_mtsy_us: 0,
            t_mtsg_us: 0,
            at_data_bytes: 0,
            mdt_data_bytes: 0,
        }],
        rules: TimingRules::default(),
    };
    Ok(timing::plan_cycle(&request)?.noncyclic)
}

/// The timing of phases 0–2 only (the slave's record in the cyclic block is a placeholder
/// of empty records; only the phase 0–2 block is laid out from it).
pub fn noncyclic_timing(config: &SlaveConfig) -> Result<CycleTiming, SlaveError> {
    let noncyclic = noncyclic_plan(config)?;
    let rate = config.bit_rate;
    let record = RECORD_HEADER_BYTES;
    Ok(CycleTiming {
        bit_rate: rate,
        cycle_time_us: config.noncyclic_cycle_us,
        nc_cycle_time_us: config.noncyclic_cycle_us,
        mst_duration_us: slot(0, MST_BYTES, rate).duration_us,
        gap_us: timing::gap_us(&TimingRules::default(), rate),
        drives: vec![DrivePlan {
            address: config.address,
            at: noncyclic.at,
            mdt_offset: 1,
            mdt_record_bytes: record as u16,
            at_record_bytes: record as u16,
        }],
        mdt: noncyclic.mdt,
        mdt_length: record as u16,
        t3_us: noncyclic.mdt.end_us(),
        t4_us: 0,
        noncyclic,
    })
}

/// The cycle of phases 3–4 from the values in `store` (what the master wrote in phase 2)
/// and the device's cyclic data lengths.
pub fn cyclic_timing<S: IdnStore + ?Sized>(
    config: &SlaveConfig,
    store: &S,
    lengths: CyclicLengths,
) -> Result<CycleTiming, SlaveError> {
    let rate = config.bit_rate;
    let cycle = read_number(store, CYCLE_TIME)?;
    let t1 = read_number(store, AT_START)?;
    let position = read_number(store, MDT_POSITION)?;
    let mdt_length = read_number(store, MDT_LENGTH)?;
    let t2 = read_number(store, MDT_START)?;
    let invalid = |idn, value, reason| SlaveError::ParameterInvalid { idn, value, reason };
    // 410B §1: cycles of 65 µs to 65 ms; TSCYC0/1 are 16-bit µs (410B §4.1 0FH, 10H).
    if !(MIN_CYCLE_US..=MAX_CYCLE_US).contains(&cycle) {
        return Err(invalid(CYCLE_TIME, cycle, "cycle time is not 65-65535 us"));
    }
    // 410B §4.2.1 TRT: 16-bit µs after the end of the MST, inside the cycle.
    if t1 >= cycle {
        return Err(invalid(AT_START, t1, "AT start not inside the cycle"));
    }
    if t2 >= cycle {
        return Err(invalid(MDT_START, t2, "MDT start not inside the cycle"));
    }
    let mdt_record = RECORD_HEADER_BYTES + u32::from(lengths.mdt_data_bytes);
    let at_record = RECORD_HEADER_BYTES + u32::from(lengths.at_data_bytes);
    // sercos-facts.md S-0-0009: byte offset counted from ADR, so the first record is at 1
    // and records start at odd offsets (whole words after ADR).
    if position == 0 || position % 2 == 0 {
        return Err(invalid(
            MDT_POSITION,
            position,
            "record offset must be odd (from ADR)",
        ));
    }
    if (position - 1).saturating_add(mdt_record) > mdt_length {
        return Err(invalid(
            MDT_POSITION,
            position,
            "record does not fit S-0-0010",
        ));
    }
    // 410B §4.2.2: LEN has 10 bits (words of one record).
    for record in [mdt_record, at_record] {
        if record.div_ceil(2) > MAX_RECORD_WORDS || record % 2 != 0 {
            return Err(SlaveError::Device(format!(
                "record of {record} bytes is not 1-{} whole words",
                MAX_RECORD_WORDS
            )));
        }
    }
    let small = |v: u32| u16::try_from(v).unwrap_or(u16::MAX);
    let at = slot(t1, 1 + at_record, rate);
    let mdt = slot(t2, 1 + mdt_length, rate);
    // The slave's chain is its AT, then the MDT (ram_layout: line order).
    if at.end_us() > t2 {
        return Err(invalid(
            AT_START,
            t1,
            "the AT must end before the MDT (S-0-0089)",
        ));
    }
    let mut timing = noncyclic_timing(config)?;
    timing.cycle_time_us = cycle;
    timing.nc_cycle_time_us = cycle;
    timing.drives = vec![DrivePlan {
        address: config.address,
        at,
        mdt_offset: small(position),
        mdt_record_bytes: small(mdt_record),
        at_record_bytes: small(at_record),
    }];
    timing.mdt = mdt;
    timing.mdt_length = small(mdt_length);
    timing.t3_us = mdt.end_us();
    Ok(timing)
}
