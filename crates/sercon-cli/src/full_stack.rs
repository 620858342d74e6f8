//! Full-stack benchmark scenarios of `sercon bench`: the whole stack running — SERCON
//! controller models on a simulated fibre ring ([`sercos_sim`]), the `sercdrv` master driver
//! on node 0 and emulated drives ([`sercos_drive::node::DriveNode`]) on the others, built by
//! [`crate::ring::build`] exactly as `sercon ring` builds them.
//!
//! Two kinds of scenario:
//!
//! * **Cyclic** (`stack-8`, …): the ring is brought up to phase 4 (not measured), then run for
//!   a given simulated time with the host writing a fresh velocity command and control word
//!   to every drive each cycle, as `sercon ring` does; measured as the real-time factor
//!   (simulated seconds per wall second).
//! * **Phase-up** (`phaseup-8`): the wall time from power-on (phase 0) until the master is in
//!   cyclic operation (phase 4).
//!
//! Each result is one JSON line with the fields of the ring benchmark
//! ([`sercos_sim::scenario::BenchResult`]) plus `"stack":"full"` and the process's peak
//! resident memory `"peak_rss_mib"` (Linux `VmHWM`, reset before each scenario where the
//! kernel allows).

use std::time::Instant as WallInstant;

use sercdrv::master::{
    MIN_SERVICE_BUFFER_WORDS, Master, MasterConfig, MasterError, MasterErrorKind, Progress,
    TELEGRAM_TYPE_CONFIGURED,
};
use sercdrv::ram_layout::{MasterBudget, MdtContainers};
use sercdrv::timing::{CycleTiming, DriveParameters};
use sercon_regs::Variant;
use sercon_regs::ram::header::Buffering;
use sercos_drive::database::IdnDatabase;
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::telegram::ControlWord;
use sercos_wire::time::{BitRate, Duration, Instant};

use crate::ring::{self, BuiltRing, RingError, RingSpec};

/// S-0-0036, velocity command (sercos-facts.md), the command of the master's default MDT list.
const VELOCITY_COMMAND: sercos_wire::idn::Idn = sercos_wire::idn::Idn::from_raw(36);

/// What a scenario measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// Cyclic operation in phase 4 after an unmeasured phase-up.
    Cyclic,
    /// The phase-up from phase 0 to phase 4.
    PhaseUp,
}

/// One full-stack scenario.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FullStackScenario {
    /// Name (`stack-8`, `phaseup-8`, …).
    pub name: String,
    /// Number of emulated drives (addresses 1…n).
    pub drives: u8,
    /// The line's bit rate.
    pub bit_rate: BitRate,
    /// Communication cycle tScyc, µs.
    pub cycle_us: u32,
    /// What is measured.
    pub measure: Measure,
    /// S-0-0015, the telegram type the master writes (7: its configured lists).
    pub telegram_type: u16,
}

impl FullStackScenario {
    /// The ring spec of this scenario: SERCON816, standard drive catalogue, 10 m fibres,
    /// no faults, no traces.
    pub fn ring_spec(&self) -> RingSpec {
        RingSpec {
            variant: Variant::Sercon816,
            bit_rate: self.bit_rate,
            cycle_us: self.cycle_us,
            drives: RingSpec::with_drives(self.drives),
            telegram_type: self.telegram_type,
            ..RingSpec::default()
        }
    }
}

/// `stack-8`: master + 8 drives, 16 Mbit/s, 250 µs cycle, phase 4 (target ≥ 50× real time).
pub fn stack_8() -> FullStackScenario {
    FullStackScenario {
        name: "stack-8".into(),
        drives: 8,
        bit_rate: BitRate::Mbit16,
        cycle_us: 250,
        measure: Measure::Cyclic,
        telegram_type: TELEGRAM_TYPE_CONFIGURED,
    }
}

/// `stack-254` (`stack-n<n>` for other sizes): master + n drives, 16 Mbit/s, 4 ms cycle,
/// standard telegram type 3 ([`BIG_RING_TELEGRAM_TYPE`]), phase 4 (the issue's target for
/// 254 drives is ≥ 10× real time).
///
/// 254 drives with the master's configured type 7 (AT records of 12 bytes, MDT records of
/// 8) need 4348 µs after the MST at 16 Mbit/s (worst-case bit stuffing, 2 µs gaps: the
/// planner, `sercdrv::timing`), more than a 4 ms cycle leaves; type 3 (AT 8 bytes, MDT 8)
/// fits (spec-notes "Master DMA layout").
pub fn stack_n(n: u8) -> FullStackScenario {
    let name = if n == 254 {
        "stack-254".to_string()
    } else {
        format!("stack-n{n}")
    };
    FullStackScenario {
        name,
        drives: n,
        bit_rate: BitRate::Mbit16,
        cycle_us: 4000,
        measure: Measure::Cyclic,
        telegram_type: BIG_RING_TELEGRAM_TYPE,
    }
}

/// The telegram type of the large-ring scenarios: standard type 3, S-0-0036 velocity
/// command in the MDT and S-0-0051 position feedback in the AT, 4 bytes each
/// (`sercdrv::master::standard_telegram`; sercos-facts.md S-0-0015 "0–6 standard"). The
/// shortest standard type that still closes a position loop over the ring (the NC
/// commands velocity, reads position) and keeps the command and feedback of the master's
/// own lists; types 0, 1 and 6 carry no feedback, 4 and 5 ask the drive for position
/// control, 5 doubles both records.
pub const BIG_RING_TELEGRAM_TYPE: u16 = 3;

/// `phaseup-8`: master + 8 drives, 16 Mbit/s, 250 µs cycle, from phase 0 to phase 4
/// (target under 250 ms of wall time).
pub fn phaseup_8() -> FullStackScenario {
    FullStackScenario {
        name: "phaseup-8".into(),
        drives: 8,
        bit_rate: BitRate::Mbit16,
        cycle_us: 250,
        measure: Measure::PhaseUp,
        telegram_type: TELEGRAM_TYPE_CONFIGURED,
    }
}

/// Every full-stack scenario `sercon bench` runs: `stack-8`, `phaseup-8`, `stack-254`.
pub fn all() -> Vec<FullStackScenario> {
    vec![stack_8(), phaseup_8(), stack_n(254)]
}

/// The scenario named `name`: one of [`all`], or `stack-n<n>` for a 4 ms ring of n drives
/// (1-254).
pub fn by_name(name: &str) -> Option<FullStackScenario> {
    if let Some(s) = all().into_iter().find(|s| s.name == name) {
        return Some(s);
    }
    let n: u8 = name.strip_prefix("stack-n")?.parse().ok()?;
    (1..=254).contains(&n).then(|| stack_n(n))
}

/// The result of one full-stack scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct FullStackResult {
    /// Scenario name.
    pub scenario: String,
    /// Drives (slaves).
    pub slaves: usize,
    /// Bit rate in Mbit/s.
    pub bit_rate_mbit: u32,
    /// Cycle in µs.
    pub cycle_us: u32,
    /// The master's phase at the end.
    pub phase: u8,
    /// Simulated seconds measured (phase 4 operation, or the phase-up).
    pub sim_s: f64,
    /// Wall seconds measured.
    pub wall_s: f64,
    /// Real-time factor: simulated seconds per wall second.
    pub rtf: f64,
    /// Wall microseconds per simulated cycle.
    pub wall_us_per_cycle: f64,
    /// Simulated seconds of the phase-up (phase 0 to phase 4).
    pub phaseup_sim_s: f64,
    /// Wall seconds of the phase-up.
    pub phaseup_wall_s: f64,
    /// Simulation events per measured cycle.
    pub events_per_cycle: f64,
    /// Host bus accesses per measured cycle during which the ring ran along, the price of
    /// exact host timing (`SimStats::host_suspensions`; spec-notes "A host's bus time").
    pub host_waits_per_cycle: f64,
    /// Peak resident memory of the process, MiB (`None` where `/proc` is missing).
    pub peak_rss_mib: Option<f64>,
}

impl FullStackResult {
    /// One JSON object on one line: the ring benchmark's fields, `"stack":"full"` and
    /// `"peak_rss_mib"` (`null` where unknown).
    pub fn to_json(&self) -> String {
        let rss = self
            .peak_rss_mib
            .map_or_else(|| "null".to_string(), |m| format!("{m:.1}"));
        format!(
            "{{\"scenario\":\"{}\",\"stack\":\"full\",\"slaves\":{},\"bit_rate_mbit\":{},\"cycle_us\":{},\"phase\":{},\"sim_s\":{:.6},\"wall_s\":{:.6},\"rtf\":{:.3},\"wall_us_per_cycle\":{:.3},\"phaseup_sim_s\":{:.6},\"phaseup_wall_s\":{:.6},\"events_per_cycle\":{:.1},\"host_waits_per_cycle\":{:.1},\"peak_rss_mib\":{}}}",
            self.scenario,
            self.slaves,
            self.bit_rate_mbit,
            self.cycle_us,
            self.phase,
            self.sim_s,
            self.wall_s,
            self.rtf,
            self.wall_us_per_cycle,
            self.phaseup_sim_s,
            self.phaseup_wall_s,
            self.events_per_cycle,
            self.host_waits_per_cycle,
            rss
        )
    }
}

/// Why a full-stack scenario failed.
#[derive(Debug, thiserror::Error)]
pub enum FullStackError {
    /// The ring could not be built or run.
    #[error(transparent)]
    Ring(#[from] RingError),
    /// The master's dual-port RAM cannot hold the ring's layout (410B §4.2), so the phase-up
    /// would end in phase 2 with the layout refused; said before simulating it.
    #[error(
        "{drives} drives do not fit the master's RAM: the layout needs {needed} words of {available}; the largest ring that fits is {largest} drives (docs/performance.md, \"Full stack\")"
    )]
    DoesNotFit {
        /// Drives asked for.
        drives: u8,
        /// Words needed.
        needed: u32,
        /// Words of the RAM.
        available: u32,
        /// The largest ring that fits.
        largest: u32,
    },
    /// The master would refuse the ring in phase 2: the cycle (or the layout) does not fit
    /// the drives' timing parameters and data lengths; said before the phase-up.
    #[error(
        "{drives} drives at {bit_rate_mbit} Mbit/s, telegram type {telegram_type}, {cycle_us} µs cycle: {} (checked before the start with the drives' own parameters; a longer --cycle-us, a higher --baud or a telegram type with less data, e.g. --telegram-type 3, may fit)",
        reason.kind
    )]
    Unplannable {
        /// Drives asked for.
        drives: usize,
        /// Bit rate, Mbit/s.
        bit_rate_mbit: u32,
        /// S-0-0015.
        telegram_type: u16,
        /// tScyc, µs.
        cycle_us: u32,
        /// The master's refusal.
        reason: MasterError,
    },
    /// The master did not reach phase 4 within the limit.
    #[error(
        "the master did not reach phase 4 within {limit_s} s simulated (phase {phase}, {progress:?})"
    )]
    NoPhase4 {
        /// The simulated-time limit, s.
        limit_s: f64,
        /// The master's phase when it gave up.
        phase: u8,
        /// The master's progress when it gave up.
        progress: Progress,
    },
}

/// A ring brought up to phase 4, ready for measured cyclic operation.
pub struct RunningStack {
    /// The ring.
    pub ring: BuiltRing,
    /// Cycle time.
    pub cycle: Duration,
    /// The drives' addresses in ring order.
    pub addresses: Vec<DriveAddress>,
    /// Simulated time of the phase-up.
    pub phaseup_sim: Duration,
    /// Wall seconds of the phase-up.
    pub phaseup_wall_s: f64,
    cycles_done: u64,
    /// The instant the run went up to (its own schedule, `phase_up_to`).
    at: Instant,
}

/// Cyclic data bytes of the master's default telegram type 7 (`MasterConfig::new`): AT
/// S-0-0011 (2) + S-0-0051 (4) + P-0-0019 (2), MDT S-0-0036 (4), as the standard catalogue
/// sizes them.
const AT_DATA_BYTES: u16 = 8;
const MDT_DATA_BYTES: u16 = 4;

/// Cyclic data bytes (AT, MDT) of `telegram_type` with the standard catalogue's lengths:
/// type 7 as above; the standard types carry 4-byte values (S-0-0036, -0040, -0047, -0051)
/// and S-0-0080 of 2 bytes.
fn data_bytes(telegram_type: u16) -> (u16, u16) {
    let Some((mdt, at)) = sercdrv::master::standard_telegram(telegram_type) else {
        return (AT_DATA_BYTES, MDT_DATA_BYTES);
    };
    let db = IdnDatabase::standard();
    let bytes = |list: &[Idn]| {
        list.iter()
            .filter_map(|&idn| db.get(idn).and_then(|p| p.attribute.fixed_words()))
            .map(|w| u16::try_from(w * 2).unwrap_or(u16::MAX))
            .sum()
    };
    (bytes(&at), bytes(&mdt))
}

/// The master's RAM budget for `s`'s smallest layout: DMA with one MDT container for every
/// record and the smallest service buffers, which the master falls back to when its default
/// (double buffer, one MDT container per drive) does not hold the ring
/// (`MasterConfig::layout_fallback`, spec-notes "Master DMA layout").
pub fn master_budget(s: &FullStackScenario) -> MasterBudget {
    let spec = s.ring_spec();
    let (at, mdt) = data_bytes(s.telegram_type);
    MasterBudget {
        buffering: Buffering::Dma,
        mdt: MdtContainers::Single,
        service_buffer_words: MIN_SERVICE_BUFFER_WORDS,
        ..MasterBudget::master_default(spec.variant, at, mdt)
    }
}

/// Cycles of phase 2 per drive a phase-up may take: phase 2 talks to one drive at a time
/// (one MDT per cycle), about 36 requests per drive at about 10 cycles each (measured with
/// `sercon ring --drives 254`: 508 requests in 5000 cycles).
pub const PHASE_UP_CYCLES_PER_DRIVE: u64 = 400;

/// Simulated time a ring of `drives` at `cycle_us` may take to reach phase 4.
pub fn phase_up_allowance(drives: u8, cycle_us: u32) -> Duration {
    Duration::from_micros(u64::from(cycle_us))
        .saturating_mul(PHASE_UP_CYCLES_PER_DRIVE.saturating_mul(u64::from(drives)))
}

/// S-0-0003, -0004, -0005, -0088, -0090: the timing parameters the master reads in phase 2
/// (sercos-facts.md, "Timing parameters").
const T1MIN: Idn = Idn::from_raw(3);
const T_ATMT: Idn = Idn::from_raw(4);
const T5: Idn = Idn::from_raw(5);
const T_MTSY: Idn = Idn::from_raw(88);
const T_MTSG: Idn = Idn::from_raw(90);

/// What drive `address` with `db` reports in phase 2 for `cfg`'s lists: its timing
/// parameters (values, µs) and the data lengths of the listed IDNs (attributes, element 3).
/// A parameter the database lacks counts as 0, a list IDN it lacks as no data: the master
/// reads the same database in phase 2 and refuses such a drive there.
pub fn drive_parameters(address: u8, db: &IdnDatabase, cfg: &MasterConfig) -> DriveParameters {
    let time = |idn| {
        db.number(idn)
            .and_then(|v| u16::try_from(v).ok())
            .unwrap_or(0)
    };
    let bytes = |list: &[Idn]| {
        let words: usize = list
            .iter()
            .filter_map(|&idn| db.read(idn, Element::Attribute).ok())
            .filter_map(|w| match w.as_slice() {
                [lo, hi] => sercos_wire::attribute::Attribute::from_words([*lo, *hi]).fixed_words(),
                _ => None,
            })
            .sum();
        u16::try_from(words.saturating_mul(2)).unwrap_or(u16::MAX)
    };
    DriveParameters {
        address,
        t1min_us: time(T1MIN),
        t_atmt_us: time(T_ATMT),
        t5_us: time(T5),
        t_mtsy_us: time(T_MTSY),
        t_mtsg_us: time(T_MTSG),
        at_data_bytes: bytes(&cfg.at_list),
        mdt_data_bytes: bytes(&cfg.mdt_list),
    }
}

/// The cycle the master will plan in phase 2 for `spec`'s ring, from the emulated drives'
/// own parameters (their IDN files or the standard catalogue): a cycle too short for the
/// drives, or a ring the RAM cannot hold, is refused here, before minutes of phase-up.
/// `None` when the master refuses the ring for another reason (a bit rate the chip does
/// not have, …): building the ring says that in its own words.
pub fn plan_ring(spec: &RingSpec) -> Result<Option<CycleTiming>, FullStackError> {
    let cfg = ring::master_config(spec)?;
    let databases = ring::databases(spec)?;
    let params = spec
        .drives
        .iter()
        .zip(&databases)
        .map(|(d, db)| drive_parameters(d.address, db, &cfg))
        .collect();
    let unplannable = |reason| FullStackError::Unplannable {
        drives: spec.drives.len(),
        bit_rate_mbit: spec.bit_rate.mbit(),
        telegram_type: spec.telegram_type,
        cycle_us: spec.cycle_us,
        reason,
    };
    let planned = Master::new(cfg).and_then(|m| m.plan_for(params));
    match planned {
        Ok((timing, _)) => Ok(Some(timing)),
        Err(e)
            if matches!(
                e.kind,
                MasterErrorKind::Timing(_) | MasterErrorKind::RingDoesNotFit { .. }
            ) =>
        {
            Err(unplannable(e))
        }
        Err(_) => Ok(None),
    }
}

/// Builds `s`'s ring (the phase-up not yet run), refusing at once a ring whose layout the
/// master's RAM cannot hold.
pub fn build(s: &FullStackScenario) -> Result<BuiltRing, FullStackError> {
    let budget = master_budget(s);
    let drives = u32::from(s.drives);
    if !budget.fits(drives) {
        return Err(FullStackError::DoesNotFit {
            drives: s.drives,
            needed: budget.words_needed(drives),
            available: u32::from(budget.variant.ram_words()),
            largest: budget.largest_ring(),
        });
    }
    let spec = s.ring_spec();
    plan_ring(&spec)?;
    Ok(ring::build(&spec, Vec::new(), false)?)
}

/// Runs `ring` until the master is in cyclic operation; the simulated time it took.
///
/// The master is checked every 16 cycles (the run is deterministic, so the check interval
/// changes only how far past the arrival the simulation stops, never the outcome); the
/// arrival is read from the master's timeline.
pub fn phase_up(
    ring: &mut BuiltRing,
    cycle: Duration,
    limit: Duration,
) -> Result<Duration, FullStackError> {
    phase_up_to(ring, cycle, limit).map(|(arrival, _)| arrival)
}

/// [`phase_up`], and the instant the run went up to. The run keeps its own schedule: the
/// simulation's time may lie past the instant it ran to, by as far as a host's bus access
/// ran on (`sercon_cli::ring::run` likewise).
fn phase_up_to(
    ring: &mut BuiltRing,
    cycle: Duration,
    limit: Duration,
) -> Result<(Duration, Instant), FullStackError> {
    let end = Instant::ZERO.saturating_add(limit);
    let step = cycle.saturating_mul(16);
    let mut at = Instant::ZERO;
    loop {
        let progress = ring.master.borrow().master.progress();
        if progress == Progress::Cyclic {
            let m = ring.master.borrow();
            let arrival = m
                .timeline
                .iter()
                .rev()
                .find(|(_, _, p)| *p == Progress::Cyclic)
                .map_or(at, |(t, _, _)| *t);
            return Ok((arrival.since_start(), at));
        }
        if progress == Progress::Halted || at >= end {
            let m = ring.master.borrow();
            return Err(FullStackError::NoPhase4 {
                limit_s: limit.as_secs_f64(),
                phase: m.master.phase(),
                progress,
            });
        }
        let next = at.saturating_add(step).min(end);
        ring.sim.run_until(next).map_err(RingError::Sim)?;
        at = next;
    }
}

impl RunningStack {
    /// Builds `s`'s ring and brings it up to phase 4 (within the ring spec's phase-up limit,
    /// 20 s simulated, or 300 s for rings of more than 8 drives: about 0.8 s per drive at 4 ms).
    pub fn start(s: &FullStackScenario) -> Result<RunningStack, FullStackError> {
        let mut spec = s.ring_spec();
        if s.drives > 8 {
            spec.phase_up_limit =
                Duration::from_secs(300).max(phase_up_allowance(s.drives, s.cycle_us));
        }
        let cycle = Duration::from_micros(u64::from(s.cycle_us));
        let wall = WallInstant::now();
        let mut ring = build(s)?;
        let (phaseup_sim, at) = phase_up_to(&mut ring, cycle, spec.phase_up_limit)?;
        let phaseup_wall_s = wall.elapsed().as_secs_f64();
        let addresses = spec
            .drives
            .iter()
            .filter_map(|d| DriveAddress::new(d.address))
            .collect();
        Ok(RunningStack {
            ring,
            cycle,
            addresses,
            phaseup_sim,
            phaseup_wall_s,
            cycles_done: 0,
            at,
        })
    }

    /// Runs `cycles` communication cycles of phase 4: before each, the host writes every
    /// drive a velocity command (a ramp, different per drive) and the control word "drive
    /// on, enable, restart" (sercos-telegrams.md control word bits 15-13), as `sercon ring`
    /// does.
    pub fn run_cycles(&mut self, cycles: u64) -> Result<(), FullStackError> {
        let control =
            ControlWord::DRIVE_ON | ControlWord::DRIVE_ENABLE | ControlWord::DRIVE_HALT_RESTART;
        for _ in 0..cycles {
            {
                let mut m = self.ring.master.borrow_mut();
                for (i, &address) in self.addresses.iter().enumerate() {
                    let v = (self.cycles_done as i64 + i as i64 * 100) % 10_000;
                    // The 4-byte command is two's complement, words low first.
                    if m.master
                        .set_command(address, VELOCITY_COMMAND, u64::from(v as u32))
                        .is_ok()
                    {
                        let _ = m.master.set_control_word(address, control);
                    }
                }
            }
            let next = self.at.saturating_add(self.cycle);
            self.ring.sim.run_until(next).map_err(RingError::Sim)?;
            self.at = next;
            self.cycles_done += 1;
        }
        Ok(())
    }

    /// The master's phase.
    pub fn phase(&self) -> u8 {
        self.ring.master.borrow().master.phase()
    }

    /// The master's progress.
    pub fn progress(&self) -> Progress {
        self.ring.master.borrow().master.progress()
    }
}

/// Peak resident memory of this process so far, MiB (Linux `/proc/self/status` `VmHWM`).
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_hwm_kib(&status).map(|kib| kib as f64 / 1024.0)
}

/// `VmHWM` in KiB from the text of `/proc/<pid>/status`.
pub fn parse_vm_hwm_kib(status: &str) -> Option<u64> {
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
}

/// Resets the peak resident memory to the current one (Linux ≥ 4.0: writing 5 to
/// `/proc/self/clear_refs`); false where the kernel does not allow it.
pub fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Runs scenario `s`: a cyclic one for `sim` of phase-4 operation after its phase-up, a
/// phase-up one from phase 0 to phase 4 (`sim` unused).
pub fn run(s: &FullStackScenario, sim: Duration) -> Result<FullStackResult, FullStackError> {
    reset_peak_rss();
    let mut stack = RunningStack::start(s)?;
    let cycle_ps = stack.cycle.as_picos().max(1);
    let counts = |st: sercos_sim::SimStats| (st.events, st.host_suspensions);
    let (sim_s, wall_s, cycles, (events, waits)) = match s.measure {
        Measure::PhaseUp => {
            let cycles = stack.phaseup_sim.as_picos().div_ceil(cycle_ps);
            (
                stack.phaseup_sim.as_secs_f64(),
                stack.phaseup_wall_s,
                cycles,
                counts(stack.ring.sim.stats()),
            )
        }
        Measure::Cyclic => {
            let cycles = (sim.as_picos() / cycle_ps).max(1);
            let before = counts(stack.ring.sim.stats());
            let wall = WallInstant::now();
            stack.run_cycles(cycles)?;
            let wall_s = wall.elapsed().as_secs_f64();
            let after = counts(stack.ring.sim.stats());
            (
                stack.cycle.saturating_mul(cycles).as_secs_f64(),
                wall_s,
                cycles,
                (
                    after.0.saturating_sub(before.0),
                    after.1.saturating_sub(before.1),
                ),
            )
        }
    };
    let per_cycle = cycles.max(1) as f64;
    Ok(FullStackResult {
        scenario: s.name.clone(),
        slaves: usize::from(s.drives),
        bit_rate_mbit: s.bit_rate.mbit(),
        cycle_us: s.cycle_us,
        phase: stack.phase(),
        sim_s,
        wall_s,
        rtf: if wall_s > 0.0 {
            sim_s / wall_s
        } else {
            f64::INFINITY
        },
        wall_us_per_cycle: wall_s * 1e6 / per_cycle,
        phaseup_sim_s: stack.phaseup_sim.as_secs_f64(),
        phaseup_wall_s: stack.phaseup_wall_s,
        events_per_cycle: events as f64 / per_cycle,
        host_waits_per_cycle: waits as f64 / per_cycle,
        peak_rss_mib: peak_rss_mib(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vm_hwm_is_read_from_the_status_text() {
        let text = "Name:\tsercon\nVmPeak:\t  20000 kB\nVmHWM:\t    5120 kB\nVmRSS:\t 4000 kB\n";
        assert_eq!(parse_vm_hwm_kib(text), Some(5120));
        assert_eq!(parse_vm_hwm_kib("VmRSS: 1 kB\n"), None);
        assert_eq!(parse_vm_hwm_kib("VmHWM: lots kB\n"), None);
    }

    #[test]
    fn json_carries_stack_full_and_the_ring_fields() {
        let r = FullStackResult {
            scenario: "stack-8".into(),
            slaves: 8,
            bit_rate_mbit: 16,
            cycle_us: 250,
            phase: 4,
            sim_s: 0.5,
            wall_s: 0.25,
            rtf: 2.0,
            wall_us_per_cycle: 125.0,
            phaseup_sim_s: 0.1,
            phaseup_wall_s: 0.05,
            events_per_cycle: 300.0,
            host_waits_per_cycle: 60.0,
            peak_rss_mib: None,
        };
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).expect("valid JSON");
        assert_eq!(v["stack"], "full");
        assert_eq!(v["scenario"], "stack-8");
        for field in [
            "slaves",
            "bit_rate_mbit",
            "cycle_us",
            "phase",
            "sim_s",
            "wall_s",
            "rtf",
        ] {
            assert!(v[field].is_number(), "{field} missing");
        }
        assert_eq!(v["host_waits_per_cycle"], 60.0);
        assert!(v["peak_rss_mib"].is_null());
    }

    #[test]
    fn scenarios_are_found_by_name() {
        assert_eq!(by_name("stack-8"), Some(stack_8()));
        assert_eq!(by_name("stack-254"), Some(stack_n(254)));
        assert_eq!(by_name("stack-n32").map(|s| s.drives), Some(32));
        assert_eq!(by_name("stack-n0"), None);
        assert_eq!(by_name("stack-n255"), None);
        assert_eq!(by_name("stack-nx"), None);
        assert_eq!(by_name("ring-8"), None);
    }

    #[test]
    fn every_ring_up_to_254_drives_fits_the_816_with_the_dma_layout() {
        // 410B §4.2 / 816 §2.3: 2048 words; the double-buffered default holds 61 drives,
        // DMA with one MDT container (410B §4.2.2) all 254 (spec-notes "Master DMA layout").
        let default =
            MasterBudget::master_default(Variant::Sercon816, AT_DATA_BYTES, MDT_DATA_BYTES);
        assert_eq!(default.largest_ring(), 61);
        assert_eq!(master_budget(&stack_n(254)).largest_ring(), 254);
        assert!(build(&stack_n(254)).is_ok());
        assert!(build(&stack_n(62)).is_ok());
    }

    #[test]
    fn scenarios_have_distinct_names_and_the_issue_figures() {
        let all = all();
        let s8 = all.iter().find(|s| s.name == "stack-8").expect("stack-8");
        assert_eq!(
            (s8.drives, s8.cycle_us, s8.bit_rate),
            (8, 250, BitRate::Mbit16)
        );
        let p = all
            .iter()
            .find(|s| s.name == "phaseup-8")
            .expect("phaseup-8");
        assert_eq!(p.measure, Measure::PhaseUp);
        let mut names: Vec<_> = all.iter().map(|s| s.name.clone()).collect();
        names.dedup();
        assert_eq!(names.len(), all.len());
    }

    // Planner (sercdrv::timing::plan_cycle) with the standard drives: 254 drives at 16 Mbit/s
    // fit 4 ms with standard type 3 (sercos-facts.md S-0-0015), not with type 7 (4348 µs).
    #[test]
    fn stack_254_plans_a_4_ms_cycle_with_telegram_type_3_and_not_with_7() {
        let s = stack_n(254);
        assert_eq!(
            (s.cycle_us, s.telegram_type, s.bit_rate),
            (4000, 3, BitRate::Mbit16)
        );
        let timing = plan_ring(&s.ring_spec()).expect("plans").expect("a timing");
        assert_eq!(timing.cycle_time_us, 4000);
        let seven = FullStackScenario {
            telegram_type: TELEGRAM_TYPE_CONFIGURED,
            ..s
        };
        assert!(matches!(
            plan_ring(&seven.ring_spec()),
            Err(FullStackError::Unplannable { .. })
        ));
        assert!(matches!(
            build(&seven),
            Err(FullStackError::Unplannable { .. })
        ));
    }

    /// The whole stack reaches phase 4 and keeps it under the bench's host load (debug
    /// build: two drives at 16 Mbit/s, 1 ms, to keep the test short).
    #[test]
    fn a_small_stack_reaches_phase_4_and_stays_there() {
        let s = FullStackScenario {
            name: "test-2".into(),
            drives: 2,
            bit_rate: BitRate::Mbit16,
            cycle_us: 1000,
            measure: Measure::Cyclic,
            telegram_type: TELEGRAM_TYPE_CONFIGURED,
        };
        let mut stack = RunningStack::start(&s).expect("phase 4");
        assert!(stack.phaseup_sim > Duration::from_picos(0));
        stack.run_cycles(20).expect("runs");
        assert_eq!(stack.phase(), 4);
        assert_eq!(stack.progress(), Progress::Cyclic);
        let r = run(&s, Duration::from_micros(5000)).expect("runs");
        assert_eq!(r.phase, 4);
        assert!(r.sim_s > 0.0049 && r.sim_s < 0.0051, "{}", r.sim_s);
    }
}
