//! The cycle's timing and telegram layout for phases 3-4: a pure function of the bit rate,
//! the cycle times and what every drive reported.
//!
//! All times are whole microseconds after the **end of the MST**, the reference of the SERCOS
//! time parameters S-0-0006/7/8/89 (sercos-facts.md, "Timing parameters": t1 "µs after the
//! MST") and of the controller's TRT and TEND (410B §4.2.1: "Time for the start of telegram in
//! µs after end of MST"; §4.2.3). The next MST starts `tScyc − MST duration` after the end of
//! this one.
//!
//! # Formula (see `docs/spec-notes.md`, "Driver timing and RAM layout (sercdrv)")
//!
//! * Telegram durations reserve the worst-case stuffing ([`worst_case_micros`]): MST 2 bytes
//!   (ADR, phase), AT `1 + 4 + AT data` bytes, MDT `1 + S-0-0010` bytes.
//! * ATs in the order the drives are given: `t1(i) = max(t1min(i), end of the previous
//!   telegram + gap)`, the first after the MST plus a gap.
//! * `t2` lies after every AT plus its drive's tATMT (S-0-0004) and after the last AT plus a
//!   gap; it lies early enough that the MDT ends `max tMTSY` (S-0-0088) before the next MST
//!   and that `t2 + MDT + max tMTSG (S-0-0090) < t3 ≤ tScyc` can hold. [`MdtPlacement`]
//!   chooses the earliest or the latest such t2.
//! * `t3 = t2 + MDT + max tMTSG + 1` (the earliest t3, one for all drives).
//! * `t4 = tScyc − max t5` (S-0-0005; the latest capture point, freshest feedback).
//! * S-0-0009 of drive i is `1 + Σ record bytes of the drives before it` (counted from the ADR
//!   byte); S-0-0010 is the sum of all MDT record bytes.

mod error;
mod telegram_time;

pub use error::TimingError;
pub use telegram_time::{
    ceil_micros, unstuffed_line_bits, worst_case_line_bits, worst_case_micros,
};

use sercos_wire::idn::Idn;
use sercos_wire::time::BitRate;

/// Bytes of the control/status word and the service info at the start of every record
/// (sercos-telegrams.md, "Data Record": 16-bit control/status word, 16-bit service channel).
pub const RECORD_HEADER_BYTES: u32 = 4;

/// Bytes of an MST after the flags: ADR and one byte of phase (sercos-telegrams.md, MST).
pub const MST_BYTES: u32 = 2;

/// Shortest cycle time the controller supports, µs (410B §1: "65 µs to 65 ms").
pub const MIN_CYCLE_US: u32 = 65;

/// Longest cycle time, µs: TSCYC0/1 are 16-bit counts of µs (410B §4.1 0FH, 10H).
pub const MAX_CYCLE_US: u32 = 65_535;

/// Most data words of one record: a data container's LEN has 10 bits (410B §4.2.2).
pub const MAX_RECORD_WORDS: u32 = 1023;

/// Most data bytes of the broadcast MDT: S-0-0010 is a 16-bit even byte count (Kollmorgen
/// S300/S700 IDN 10: "even number ... not exceeding 65534").
pub const MAX_MDT_BYTES: u32 = 65_534;

/// What one drive reported in phase 2 and what it carries cyclically.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveParameters {
    /// Drive address, 1-254 (sercos-telegrams.md, ADR).
    pub address: u8,
    /// S-0-0003, minimum AT transmit starting time t1min, µs.
    #[doc(alias = "S-0-0003")]
    pub t1min_us: u16,
    /// S-0-0004, transmit/receive transition time tATMT, µs.
    #[doc(alias = "S-0-0004")]
    pub t_atmt_us: u16,
    /// S-0-0005, minimum feedback acquisition time t5, µs.
    #[doc(alias = "S-0-0005")]
    pub t5_us: u16,
    /// S-0-0088, receive-to-receive recovery time tMTSY, µs.
    #[doc(alias = "S-0-0088")]
    pub t_mtsy_us: u16,
    /// S-0-0090, command value transmit (copy) time tMTSG, µs.
    #[doc(alias = "S-0-0090")]
    pub t_mtsg_us: u16,
    /// Cyclic data bytes in the drive's AT (after status word and service info).
    pub at_data_bytes: u16,
    /// Cyclic data bytes in the drive's MDT record (after control word and service info).
    pub mdt_data_bytes: u16,
}

/// Where the MDT goes between the last AT and the end of the cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MdtPlacement {
    /// As early as the ATs and every tATMT allow: the shortest used part of the cycle.
    #[default]
    AfterAts,
    /// As late as tMTSY and t3 allow, leaving the master the most time between the ATs and
    /// the MDT (what the captures' commercial master does).
    EndOfCycle,
}

/// The master's own choices that the drives do not dictate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimingRules {
    /// Least gap between two telegrams, µs; the planner uses at least 16 bit times (two
    /// flags' worth) whichever is longer.
    pub min_gap_us: u16,
    /// Where the MDT goes.
    pub mdt_placement: MdtPlacement,
}

impl Default for TimingRules {
    fn default() -> Self {
        TimingRules {
            min_gap_us: 2,
            mdt_placement: MdtPlacement::AfterAts,
        }
    }
}

/// Everything the planner needs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TimingRequest {
    /// The line's bit rate.
    pub bit_rate: BitRate,
    /// S-0-0002, communication cycle time tScyc, µs.
    #[doc(alias = "S-0-0002")]
    pub cycle_time_us: u32,
    /// S-0-0001, NC cycle time, µs: a whole multiple of tScyc.
    #[doc(alias = "S-0-0001")]
    pub nc_cycle_time_us: u32,
    /// The drives, in the order their ATs follow each other.
    pub drives: Vec<DriveParameters>,
    /// The master's choices.
    pub rules: TimingRules,
}

/// One telegram's place in the cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TelegramSlot {
    /// Start, µs after the end of the MST.
    pub start_us: u32,
    /// Worst-case duration on the line, µs (rounded up).
    pub duration_us: u32,
    /// Telegram bytes: ADR and data, without FCS and flags.
    pub bytes: u32,
}

impl TelegramSlot {
    /// End of the telegram (start + worst-case duration), µs after the end of the MST.
    pub const fn end_us(&self) -> u32 {
        self.start_us + self.duration_us
    }

    /// Data words after the ADR byte, rounded up (what the controller's TLEN counts,
    /// 410B §4.2.1: "Length of telegram in data words (not including address)").
    pub const fn data_words(&self) -> u32 {
        self.bytes.saturating_sub(1).div_ceil(2)
    }
}

/// One drive's part of the plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrivePlan {
    /// The drive's address.
    pub address: u8,
    /// Its AT: start is t1 (S-0-0006).
    pub at: TelegramSlot,
    /// S-0-0009: byte offset of its record in the MDT, counted from the ADR byte (the first
    /// record is at 1).
    #[doc(alias = "S-0-0009")]
    pub mdt_offset: u16,
    /// Bytes of its MDT record (control word, service info, command data).
    pub mdt_record_bytes: u16,
    /// Bytes of its AT record (status word, service info, feedback data).
    pub at_record_bytes: u16,
}

impl DrivePlan {
    /// S-0-0006, the AT transmission starting time t1, µs.
    #[doc(alias = "S-0-0006")]
    pub const fn t1_us(&self) -> u32 {
        self.at.start_us
    }
}

/// The telegrams of phases 0-2: MST, one unicast MDT and one AT per cycle, 4-byte records.
///
/// The drives' timing parameters are only read in phase 2, so the master cannot fit these
/// slots to them: the AT goes right after the MST (plus a gap) and the MDT at half the cycle,
/// leaving the unknown tATMT and tMTSY the most room on both sides (reading chosen, see
/// `docs/spec-notes.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NonCyclicPlan {
    /// The AT slot.
    pub at: TelegramSlot,
    /// The MDT slot.
    pub mdt: TelegramSlot,
}

/// The computed cycle: timing and telegram layout of phases 3-4 (and the slots of 0-2).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CycleTiming {
    /// The line's bit rate.
    pub bit_rate: BitRate,
    /// S-0-0002, tScyc, µs.
    pub cycle_time_us: u32,
    /// S-0-0001, NC cycle time, µs.
    pub nc_cycle_time_us: u32,
    /// Worst-case duration of the MST, µs.
    pub mst_duration_us: u32,
    /// The gap used between telegrams, µs.
    pub gap_us: u32,
    /// One entry per drive, in AT order.
    pub drives: Vec<DrivePlan>,
    /// The broadcast MDT: start is t2 (S-0-0089).
    pub mdt: TelegramSlot,
    /// S-0-0010, data bytes of the MDT.
    #[doc(alias = "S-0-0010")]
    pub mdt_length: u16,
    /// S-0-0008, command value valid time t3, µs.
    #[doc(alias = "S-0-0008")]
    pub t3_us: u32,
    /// S-0-0007, feedback acquisition capture point t4, µs.
    #[doc(alias = "S-0-0007")]
    pub t4_us: u32,
    /// Phases 0-2.
    pub noncyclic: NonCyclicPlan,
}

impl CycleTiming {
    /// S-0-0089, the MDT transmission starting time t2, µs.
    #[doc(alias = "S-0-0089")]
    pub const fn t2_us(&self) -> u32 {
        self.mdt.start_us
    }

    /// Time after the end of MST at which the last telegram has ended, µs: the end marker's
    /// TEND (410B §4.2.3). The MDT comes after every AT, so it is the MDT's end.
    #[doc(alias = "TEND")]
    pub const fn tend_us(&self) -> u32 {
        self.mdt.end_us()
    }

    /// Time from the end of this MST to the start of the next one, µs.
    pub const fn window_us(&self) -> u32 {
        self.cycle_time_us.saturating_sub(self.mst_duration_us)
    }

    /// The plan of drive `address`, if it is in the ring.
    pub fn drive(&self, address: u8) -> Option<&DrivePlan> {
        self.drives.iter().find(|d| d.address == address)
    }

    /// The values the master writes to drive `address` in phase 2, in the order the captures'
    /// master writes them: S-0-0001, S-0-0002, S-0-0006, S-0-0089, S-0-0008, S-0-0007,
    /// S-0-0009, S-0-0010. Every value fits 16 bits because tScyc does.
    pub fn parameter_writes(&self, address: u8) -> Option<[(Idn, u32); 8]> {
        let d = self.drive(address)?;
        Some([
            (Idn::from_raw(1), self.nc_cycle_time_us),
            (Idn::from_raw(2), self.cycle_time_us),
            (Idn::from_raw(6), d.t1_us()),
            (Idn::from_raw(89), self.t2_us()),
            (Idn::from_raw(8), self.t3_us),
            (Idn::from_raw(7), self.t4_us),
            (Idn::from_raw(9), u32::from(d.mdt_offset)),
            (Idn::from_raw(10), u32::from(self.mdt_length)),
        ])
    }
}

fn slot(start_us: u32, bytes: u32, rate: BitRate) -> TelegramSlot {
    TelegramSlot {
        start_us,
        duration_us: u32::try_from(worst_case_micros(u64::from(bytes), rate)).unwrap_or(u32::MAX),
        bytes,
    }
}

/// The gap between telegrams: `min_gap_us` or 16 bit times, whichever is longer.
pub fn gap_us(rules: &TimingRules, rate: BitRate) -> u32 {
    let flags = u32::try_from(ceil_micros(rate.duration_of_bits(16))).unwrap_or(u32::MAX);
    u32::from(rules.min_gap_us).max(flags)
}

fn check_request(req: &TimingRequest) -> Result<(), TimingError> {
    // 410B §1: cycles of 65 µs to 65 ms; 410B §4.1 TSCYC0/1: 16 bits of µs.
    if !(MIN_CYCLE_US..=MAX_CYCLE_US).contains(&req.cycle_time_us) {
        return Err(TimingError::CycleTimeOutOfRange {
            cycle_us: req.cycle_time_us,
            min_us: MIN_CYCLE_US,
            max_us: MAX_CYCLE_US,
        });
    }
    // sercos-facts.md S-0-0001 NC cycle time: the NC runs every n-th communication cycle.
    if req.nc_cycle_time_us < req.cycle_time_us
        || req.nc_cycle_time_us % req.cycle_time_us != 0
        || req.nc_cycle_time_us > MAX_CYCLE_US
    {
        return Err(TimingError::NcCycleNotMultiple {
            nc_cycle_us: req.nc_cycle_time_us,
            cycle_us: req.cycle_time_us,
        });
    }
    if req.drives.is_empty() {
        return Err(TimingError::NoDrives);
    }
    if req.drives.len() > 254 {
        return Err(TimingError::TooManyDrives {
            count: req.drives.len(),
        });
    }
    let mut seen = [false; 256];
    for d in &req.drives {
        // sercos-telegrams.md, ADR: drive addresses are 1-254.
        if d.address == 0 || d.address == 255 {
            return Err(TimingError::InvalidAddress { address: d.address });
        }
        if let Some(flag) = seen.get_mut(usize::from(d.address)) {
            if *flag {
                return Err(TimingError::DuplicateAddress { address: d.address });
            }
            *flag = true;
        }
        for (telegram, bytes) in [("AT", d.at_data_bytes), ("MDT", d.mdt_data_bytes)] {
            // sercos-telegrams.md, Data Record: a data block of 16-bit words.
            if bytes % 2 != 0 {
                return Err(TimingError::OddDataLength {
                    address: d.address,
                    telegram,
                    bytes: u32::from(bytes),
                });
            }
            // 410B §4.2.2: LEN (10 bits) counts the words of one record's container.
            let words = (RECORD_HEADER_BYTES + u32::from(bytes)) / 2;
            if words > MAX_RECORD_WORDS {
                return Err(TimingError::TelegramTooLong {
                    address: d.address,
                    telegram: if telegram == "AT" {
                        "AT record"
                    } else {
                        "MDT record"
                    },
                    words,
                    max_words: MAX_RECORD_WORDS,
                });
            }
        }
    }
    Ok(())
}

/// Plans the cycle of phases 3-4 (and the slots of phases 0-2) or says why it cannot be done.
///
/// Checks, for every drive (sercos-facts.md, relations a master checks): t1min ≤ t1 and
/// t1 + AT + tATMT ≤ t2 (so t1 < t2 − tATMT); t4 ≤ tScyc − t5;
/// t2 + MDT duration + S-0-0090 < t3 ≤ tScyc; and that the MDT plus S-0-0088 ends before the
/// next MST.
pub fn plan_cycle(req: &TimingRequest) -> Result<CycleTiming, TimingError> {
    check_request(req)?;
    let rate = req.bit_rate;
    let cycle = req.cycle_time_us;
    let gap = gap_us(&req.rules, rate);
    let mst = slot(0, MST_BYTES, rate);
    let window = cycle.saturating_sub(mst.duration_us);

    // ATs one after another, each at its t1min or after the previous telegram and a gap.
    let mut drives = Vec::with_capacity(req.drives.len());
    let mut earliest_t2 = 0u32;
    let mut next_free = gap;
    let mut mdt_offset = 1u32; // S-0-0009 counts from ADR (spec-notes, capture decoding).
    for d in &req.drives {
        let at_record = RECORD_HEADER_BYTES + u32::from(d.at_data_bytes);
        let mdt_record = RECORD_HEADER_BYTES + u32::from(d.mdt_data_bytes);
        let t1 = u32::from(d.t1min_us).max(next_free);
        let at = slot(t1, 1 + at_record, rate);
        next_free = at.end_us().saturating_add(gap);
        // sercos-facts.md: t1 < t2 − tATMT; we keep tATMT after the end of the AT.
        earliest_t2 = earliest_t2
            .max(next_free)
            .max(at.end_us().saturating_add(u32::from(d.t_atmt_us)));
        drives.push(DrivePlan {
            address: d.address,
            at,
            mdt_offset: u16::try_from(mdt_offset).unwrap_or(u16::MAX),
            mdt_record_bytes: u16::try_from(mdt_record).unwrap_or(u16::MAX),
            at_record_bytes: u16::try_from(at_record).unwrap_or(u16::MAX),
        });
        mdt_offset = mdt_offset.saturating_add(mdt_record);
    }
    let mdt_length = mdt_offset - 1;
    if mdt_length > MAX_MDT_BYTES {
        return Err(TimingError::TelegramTooLong {
            address: 0,
            telegram: "MDT",
            words: mdt_length / 2,
            max_words: MAX_MDT_BYTES / 2,
        });
    }
    let mdt_duration = slot(0, 1 + mdt_length, rate).duration_us;

    let (max_mtsy, max_mtsg, max_t5) = maxima(&req.drives);
    // Bosch Servodyn-D S-0-0088: the drive needs tMTSY between the end of the MDT and the
    // next MST; the master accounts for it when computing t2.
    let latest_by_mtsy = window.checked_sub(max_mtsy.1 + mdt_duration);
    // sercos-facts.md: t2 + MDT duration + S-0-0090 < t3 ≤ tScyc.
    let latest_by_t3 = cycle.checked_sub(max_mtsg.1 + mdt_duration + 1);
    let latest_t2 = match (latest_by_mtsy, latest_by_t3) {
        (Some(a), Some(b)) => a.min(b),
        (None, _) => {
            return Err(TimingError::CycleTooShort {
                what: "MDT and tMTSY (S-0-0088)",
                needed_us: max_mtsy.1 + mdt_duration,
                available_us: window,
                cycle_us: cycle,
            });
        }
        (Some(_), None) => {
            return Err(t3_impossible(0, max_mtsg, mdt_duration, cycle));
        }
    };
    if earliest_t2 > latest_t2 {
        return Err(explain_late(
            req,
            &drives,
            gap,
            latest_t2,
            earliest_t2,
            mdt_duration,
            max_mtsy,
            max_mtsg,
            window,
        ));
    }
    let t2 = match req.rules.mdt_placement {
        MdtPlacement::AfterAts => earliest_t2,
        MdtPlacement::EndOfCycle => latest_t2,
    };
    let t3 = t2 + mdt_duration + max_mtsg.1 + 1;
    // sercos-facts.md: t4 ≤ tScyc − t5; the latest such point gives the freshest feedback.
    let t4 = cycle
        .checked_sub(max_t5.1)
        .ok_or(TimingError::T4Impossible {
            address: max_t5.0,
            t5_us: max_t5.1,
            cycle_us: cycle,
        })?;
    let noncyclic = plan_noncyclic(rate, cycle, gap, window)?;
    Ok(CycleTiming {
        bit_rate: rate,
        cycle_time_us: cycle,
        nc_cycle_time_us: req.nc_cycle_time_us,
        mst_duration_us: mst.duration_us,
        gap_us: gap,
        drives,
        mdt: slot(t2, 1 + mdt_length, rate),
        mdt_length: u16::try_from(mdt_length).unwrap_or(u16::MAX),
        t3_us: t3,
        t4_us: t4,
        noncyclic,
    })
}

/// (address, value) of the largest tMTSY, tMTSG and t5.
fn maxima(drives: &[DriveParameters]) -> ((u8, u32), (u8, u32), (u8, u32)) {
    let pick = |f: fn(&DriveParameters) -> u16| {
        drives
            .iter()
            .map(|d| (d.address, u32::from(f(d))))
            .fold((0u8, 0u32), |best, x| if x.1 > best.1 { x } else { best })
    };
    (
        pick(|d| d.t_mtsy_us),
        pick(|d| d.t_mtsg_us),
        pick(|d| d.t5_us),
    )
}

fn t3_impossible(t2: u32, max_mtsg: (u8, u32), mdt_duration: u32, cycle: u32) -> TimingError {
    TimingError::T3Impossible {
        address: max_mtsg.0,
        t2_us: t2,
        mdt_us: mdt_duration,
        t_mtsg_us: max_mtsg.1,
        cycle_us: cycle,
    }
}

/// Why no t2 fits: a drive whose t1min pushes its AT too late, t3, or plain lack of time.
#[allow(clippy::too_many_arguments)]
fn explain_late(
    req: &TimingRequest,
    drives: &[DrivePlan],
    gap: u32,
    latest_t2: u32,
    earliest_t2: u32,
    mdt_duration: u32,
    max_mtsy: (u8, u32),
    max_mtsg: (u8, u32),
    window: u32,
) -> TimingError {
    let mut previous_end = 0u32;
    for (p, d) in drives.iter().zip(&req.drives) {
        let needed = p.at.end_us().saturating_add(u32::from(d.t_atmt_us));
        let pushed_by_t1min = u32::from(d.t1min_us) > previous_end.saturating_add(gap);
        if needed > latest_t2 && pushed_by_t1min {
            return TimingError::AtTooLate {
                address: d.address,
                t1min_us: u32::from(d.t1min_us),
                t1_us: p.at.start_us,
                needed_us: needed,
                latest_us: latest_t2,
            };
        }
        previous_end = p.at.end_us();
    }
    let mtsy_need = earliest_t2 + mdt_duration + max_mtsy.1;
    if mtsy_need > window {
        return TimingError::CycleTooShort {
            what: "ATs, tATMT (S-0-0004), MDT and tMTSY (S-0-0088)",
            needed_us: mtsy_need,
            available_us: window,
            cycle_us: req.cycle_time_us,
        };
    }
    t3_impossible(earliest_t2, max_mtsg, mdt_duration, req.cycle_time_us)
}

/// Slots of phases 0-2: AT right after the MST plus a gap, MDT at half the cycle
/// (4-byte records: sercos-telegrams.md, "During Phase 2, the Data Block ... has a length
/// of 0").
fn plan_noncyclic(
    rate: BitRate,
    cycle: u32,
    gap: u32,
    window: u32,
) -> Result<NonCyclicPlan, TimingError> {
    let at = slot(gap, 1 + RECORD_HEADER_BYTES, rate);
    let mdt = slot(
        (cycle / 2).max(at.end_us() + gap),
        1 + RECORD_HEADER_BYTES,
        rate,
    );
    if mdt.end_us() > window {
        return Err(TimingError::CycleTooShort {
            what: "the phase 0-2 AT and MDT",
            needed_us: mdt.end_us(),
            available_us: window,
            cycle_us: cycle,
        });
    }
    Ok(NonCyclicPlan { at, mdt })
}
