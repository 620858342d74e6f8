//! Runs a ring: phase-up to phase 4, then `run_for` of cyclic operation with the motion
//! profile, faults placed from the first arrival in phase 4, the chips' line status and
//! MST counters sampled every cycle; gathers the [`RingReport`].

use sercdrv::master::Progress;
use sercon_model::pins::Pin;
use sercon_regs::SerconBus;
use sercon_regs::Variant;
use sercon_regs::ram::NMSTERR;
use sercos_sim::recorder::TraceOutput;
use sercos_wire::address::DriveAddress;
use sercos_wire::service_transcript::{TranscriptBuilder, TranscriptEntry};
use sercos_wire::telegram::ControlWord;
use sercos_wire::time::{Duration, Instant};

use super::error::RingError;
use super::fault_spec::{FaultWhat, NodeRef};
use super::probes::VELOCITY_COMMAND;
use super::report::{
    AxisReport, DriveReport, MasterEvent, RingEvent, RingEventKind, RingReport, RunResult,
};
use super::setup::{self, BuiltRing};
use super::spec::RingSpec;

/// 410B §4.1 2H.13 FIBBR: no edges on the receive data (fibre broken).
const FIBBR: u16 = 1 << 13;
/// Register 2H, the status register (410B §4.1).
const STATUS_REGISTER: u8 = 0x02;

/// Where a run stands, for progress displays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunProgress {
    /// Simulated time so far.
    pub now: Duration,
    /// The master's phase.
    pub phase: u8,
    /// Simulated time of phase-4 operation so far (0 before phase 4).
    pub operating: Duration,
    /// Phase-4 operation asked for.
    pub run_for: Duration,
    /// The run is on the simulator's reference path (asked for, or run again there after
    /// the fast path's collisions, [`run`]).
    pub reference: bool,
}

/// A finished run: its report, the traces, and the master's service-channel transcript
/// (when asked for).
#[derive(Debug)]
pub struct RingOutcome {
    /// The report.
    pub report: RingReport,
    /// The traces the simulator kept (empty where off).
    pub traces: TraceOutput,
    /// The master's service channel, rebuilt from its telegrams on fibre 0.
    pub transcript: Vec<TranscriptEntry>,
}

/// What the runner samples from the chips every cycle.
struct Watch {
    powered: Vec<bool>,
    mst_count: Vec<u16>,
    mst_errors: Vec<u64>,
    first_dark: Option<usize>,
    lost: Vec<bool>,
    events: Vec<(Instant, RingEventKind)>,
}

/// Runs `spec`, calling `progress` once per cycle. A run on the simulator's fast path in
/// which telegrams met at a repeater's output where the fast path cannot follow the chips
/// (`sercos_sim::SimStats::fast_path_collisions`; spec-notes "Repeater collisions") is run
/// again on the reference path, and that run is the outcome (its report says so). A ring
/// with a fault other than clock drift runs on the reference path from the start.
pub fn run(
    spec: &RingSpec,
    progress: &mut dyn FnMut(&RunProgress),
) -> Result<RingOutcome, RingError> {
    if !spec.reference && (faults_beyond_drift(spec) || traces_drive_reactn(spec)) {
        // A fault other than drift, or a drive's REACTN in the VCD: the reference path at
        // once (spec-notes "The ring command", faults on the reference path, REACTN).
        let mut reference = spec.clone();
        reference.reference = true;
        return Ok(run_once(&reference, progress)?.0);
    }
    let (outcome, collisions) = run_once(spec, progress)?;
    if spec.reference || collisions == 0 {
        return Ok(outcome);
    }
    let mut reference = spec.clone();
    reference.reference = true;
    let (mut outcome, _) = run_once(&reference, progress)?;
    outcome.report.fast_path_collisions = Some(collisions);
    Ok(outcome)
}

/// Whether `spec` has a fault other than clock drift (a break, a power-off, bit errors, a
/// burst, distortion). With any of them the simulator's fast path hands the master's
/// telegrams to the chips to forward, hop by hop, and follows the faults' effects only in
/// part (a slave's telegram carried ahead of what is still in the chips; a repair's replay
/// without the filler after it: spec-notes "Fast path = reference path"): such runs counted
/// collisions and ran again on the reference path (16 drives, one burst: 692 counted, 0.64 s
/// against 0.39 s on the reference path alone; one break into drive 5 of 32: 3 627, 2.1 s
/// against 1.3 s), and where they did not, the fast path saved ≈ 10 % (16 drives, bit errors:
/// 0.46 s against 0.51 s). A drifting clock alone leaves the ring plain (the fast path at
/// full speed: 0.20 s against 0.39 s).
fn faults_beyond_drift(spec: &RingSpec) -> bool {
    spec.faults
        .iter()
        .any(|f| !matches!(f.what, FaultWhat::Drift { .. }))
}

/// Whether the VCD holds a drive's REACTN (410B §2, receive active; 3H.15). On the fast
/// path a drive's receiver is not given the other drives' telegrams that pass it (they go
/// from its chip's repeater straight on), so its REACTN does not fall for them (spec-notes
/// "Fast path = reference path", limit on REACTN); the reference path gives every receiver
/// all it hears. The master's REACTN is the same on both.
fn traces_drive_reactn(spec: &RingSpec) -> bool {
    let t = &spec.traces;
    t.vcd.is_some()
        && t.vcd_pins
            .as_ref()
            .is_some_and(|p| p.contains(&Pin::Reactn))
        && t.vcd_nodes
            .as_ref()
            .is_none_or(|n| n.iter().any(|n| matches!(n, NodeRef::Drive(_))))
}

/// [`run`] on the path `spec` names; with the fast path's collisions.
fn run_once(
    spec: &RingSpec,
    progress: &mut dyn FnMut(&RunProgress),
) -> Result<(RingOutcome, u64), RingError> {
    setup::validate(spec)?;
    if spec.traces.transcript.is_some() {
        if spec.traces.log_segment.is_some_and(|s| s != 0) {
            return Err(RingError::Spec(
                "--transcript reads fibre 0: use --log-segment 0 or leave it out".into(),
            ));
        }
        let text_log = spec
            .traces
            .log
            .as_ref()
            .is_some_and(|p| !p.extension().is_some_and(|e| e == "jsonl" || e == "json"));
        if text_log {
            return Err(RingError::Spec(
                "--transcript is built from the JSON log: name the --log file *.jsonl, or leave --log out"
                    .into(),
            ));
        }
    }
    let cycle = Duration::from_micros(u64::from(spec.cycle_us));
    // Faults count from the first arrival in phase 4: find it on the same ring without
    // faults (the run is deterministic, and the faults only act from then on).
    let origin = if spec.faults.is_empty() {
        None
    } else {
        let mut probe = setup::build(spec, Vec::new(), false)?;
        phase_up(&mut probe, spec, cycle, &mut |_, _| {})?.0
    };
    let faults = match origin {
        Some(t) => setup::sim_faults(spec, t, t.saturating_add(spec.run_for))?,
        None => Vec::new(),
    };
    let mut ring = setup::build(spec, faults, true)?;
    let mut watch = Watch {
        powered: vec![true; ring.drives.len() + 1],
        mst_count: vec![0; ring.drives.len() + 1],
        mst_errors: vec![0; ring.drives.len() + 1],
        first_dark: None,
        lost: vec![false; ring.drives.len() + 1],
        events: Vec::new(),
    };
    let mut on_cycle = |ring: &mut BuiltRing, p: &RunProgress| {
        sample(ring, spec, &mut watch, Instant::ZERO.saturating_add(p.now));
        progress(p);
    };
    // The runner keeps its own time (the instants it ran to): the simulation's may lie past
    // them, by as far as a host's bus access ran on, and by how far depends on the path
    // (the reference path runs more events inside an access), so the commands and the next
    // instant are taken from the run's own schedule, the same on both.
    let (reached, mut at) = phase_up(&mut ring, spec, cycle, &mut on_cycle)?;
    if let Some(start) = reached {
        let end = start.saturating_add(spec.run_for);
        let addresses: Vec<Option<DriveAddress>> = spec
            .drives
            .iter()
            .map(|d| DriveAddress::new(d.address))
            .collect();
        // sercos-telegrams.md control word: drive on (15), enable (14), restart (13);
        // operation mode bits 9-8 = 0 choose S-0-0032, velocity control.
        let control =
            ControlWord::DRIVE_ON | ControlWord::DRIVE_ENABLE | ControlWord::DRIVE_HALT_RESTART;
        while at < end {
            let now = at;
            let elapsed = now.saturating_duration_since(start);
            {
                let mut m = ring.master.borrow_mut();
                if m.master.progress() == Progress::Cyclic {
                    for (i, (address, drive)) in addresses.iter().zip(&ring.drives).enumerate() {
                        let Some(address) = *address else { continue };
                        let v = spec.profile.velocity_command(i, elapsed);
                        // Words low first; the 4-byte command is two's complement.
                        if m.master
                            .set_command(address, VELOCITY_COMMAND, u64::from(v as u32))
                            .is_ok()
                        {
                            drive.borrow().sent.borrow_mut().insert(i128::from(v));
                            let _ = m.master.set_control_word(address, control);
                        }
                    }
                }
            }
            let next = now.saturating_add(cycle).min(end);
            ring.sim.run_until(next).map_err(RingError::Sim)?;
            at = next;
            let p = RunProgress {
                now: next.since_start(),
                phase: ring.master.borrow().master.phase(),
                operating: next.saturating_duration_since(start),
                run_for: spec.run_for,
                reference: spec.reference,
            };
            on_cycle(&mut ring, &p);
        }
    }
    let traces = ring.sim.finish().map_err(RingError::Sim)?;
    let transcript = if spec.traces.transcript.is_some() {
        transcript_of(&traces.log)
    } else {
        Vec::new()
    };
    let collisions = ring.sim.stats().fast_path_collisions;
    let report = gather(&mut ring, spec, reached, watch, at);
    Ok((
        RingOutcome {
            report,
            traces,
            transcript,
        },
        collisions,
    ))
}

/// Runs cycle by cycle until the master is in cyclic operation (phase 4), halts, or the
/// limit passes; the time it got there, and the instant the run went up to.
fn phase_up(
    ring: &mut BuiltRing,
    spec: &RingSpec,
    cycle: Duration,
    on_cycle: &mut dyn FnMut(&mut BuiltRing, &RunProgress),
) -> Result<(Option<Instant>, Instant), RingError> {
    let limit = Instant::ZERO.saturating_add(spec.phase_up_limit);
    let mut at = Instant::ZERO;
    while at < limit {
        let next = at.saturating_add(cycle).min(limit);
        ring.sim.run_until(next).map_err(RingError::Sim)?;
        at = next;
        let (phase, progress) = {
            let m = ring.master.borrow();
            (m.master.phase(), m.master.progress())
        };
        on_cycle(
            ring,
            &RunProgress {
                now: next.since_start(),
                phase,
                operating: Duration::from_picos(0),
                run_for: spec.run_for,
                reference: spec.reference,
            },
        );
        match progress {
            Progress::Cyclic => {
                let at = ring
                    .master
                    .borrow()
                    .timeline
                    .iter()
                    .rev()
                    .find(|(_, _, p)| *p == Progress::Cyclic)
                    .map_or(next, |(t, _, _)| *t);
                return Ok((Some(at), next));
            }
            Progress::Halted => return Ok((None, next)),
            _ => {}
        }
    }
    Ok((None, at))
}

/// Name of node `i` (0 the master).
fn node_name(spec: &RingSpec, i: usize) -> String {
    match i.checked_sub(1).and_then(|k| spec.drives.get(k)) {
        Some(d) => format!("drive {}", d.address),
        None => "master".into(),
    }
}

/// Samples power, line status and MST counters of every node at `now`, the instant the run
/// went up to.
fn sample(ring: &mut BuiltRing, spec: &RingSpec, w: &mut Watch, now: Instant) {
    let n = ring.drives.len() + 1;
    let mut first_dark = None;
    // Ring order after the master: drive 1 … drive n, then the master's own receiver.
    for i in (1..n).chain(std::iter::once(0)) {
        let powered = ring.sim.powered(i);
        let address = i
            .checked_sub(1)
            .and_then(|k| spec.drives.get(k))
            .map(|d| d.address);
        if let (Some(drive), Some(was)) = (address, w.powered.get_mut(i))
            && *was != powered
        {
            *was = powered;
            w.events.push((
                now,
                if powered {
                    RingEventKind::PowerOn { drive }
                } else {
                    RingEventKind::PowerOff { drive }
                },
            ));
            if let Some(c) = w.mst_count.get_mut(i) {
                *c = 0; // a fresh chip counts from 0
            }
        }
        if !powered {
            continue;
        }
        let Some(chip) = ring.sim.chip_mut(i) else {
            continue;
        };
        if first_dark.is_none() && chip.read_register(STATUS_REGISTER) & FIBBR != 0 {
            first_dark = Some(i);
        }
        if let Some(drive) = address {
            // 410B §4.2 word 10 NMSTERR: error counter MST (counts up, wraps).
            let count = chip.read_ram(NMSTERR);
            let prev = w.mst_count.get(i).copied().unwrap_or(0);
            let delta = u64::from(count.wrapping_sub(prev));
            if let Some(c) = w.mst_count.get_mut(i) {
                *c = count;
            }
            if let Some(e) = w.mst_errors.get_mut(i) {
                *e += delta;
            }
            let lost = delta > 0;
            if let Some(was) = w.lost.get_mut(i) {
                if lost && !*was {
                    w.events.push((now, RingEventKind::LostMsts { drive }));
                }
                *was = lost;
            }
        }
    }
    if first_dark != w.first_dark {
        let kind = match first_dark {
            Some(i) => RingEventKind::Open {
                first_dark: node_name(spec, i),
            },
            None => RingEventKind::Closed,
        };
        // Receivers notice the loss of light at different times (410B §4.1 2H.13 FIBBR
        // needs a stretch without edges): while the ring stays open, a node earlier in ring
        // order that goes dark a moment later replaces the first report (docs/spec-notes.md,
        // "The ring command").
        let reopen = w.first_dark.is_some() && first_dark.is_some();
        let last_open = w
            .events
            .iter()
            .rposition(|(_, k)| matches!(k, RingEventKind::Open { .. } | RingEventKind::Closed));
        match last_open {
            Some(j) if reopen => {
                if let Some(e) = w.events.get_mut(j) {
                    e.1 = kind;
                }
            }
            _ => w.events.push((now, kind)),
        }
        w.first_dark = first_dark;
    }
}

/// The master's service-channel transcript from a JSON-lines log (its telegrams on fibre 0).
fn transcript_of(log: &[u8]) -> Vec<TranscriptEntry> {
    let text = String::from_utf8_lossy(log);
    let mut b = TranscriptBuilder::new();
    let mut index = 0u64;
    for line in text.lines() {
        let Ok(v) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        if v["segment"] != 0 || v["origin"] != "master" || v["fcs"] != "ok" {
            continue;
        }
        let Some(hex) = v["bytes"].as_str() else {
            continue;
        };
        let bytes: Vec<u8> = (0..hex.len() / 2)
            .filter_map(|i| hex.get(2 * i..2 * i + 2))
            .filter_map(|h| u8::from_str_radix(h, 16).ok())
            .collect();
        b.master_telegram(&bytes, index);
        index += 1;
    }
    b.finish()
}

fn secs(t: Instant) -> f64 {
    t.since_start().as_secs_f64()
}

/// Gathers the report at the end of the run.
fn gather(
    ring: &mut BuiltRing,
    spec: &RingSpec,
    reached: Option<Instant>,
    watch: Watch,
    end: Instant,
) -> RingReport {
    let m = ring.master.borrow();
    let status = m.master.status();
    let timing = m.master.timing();
    let telegram_type = m.master.config().telegram_type;
    let mut events = watch.events;
    for (t, e) in &m.errors {
        events.push((
            *t,
            RingEventKind::MasterError {
                text: e.to_string(),
            },
        ));
    }
    let mut drives = Vec::new();
    for (k, (d, probe)) in spec.drives.iter().zip(&ring.drives).enumerate() {
        let p = probe.borrow();
        // Phase-4 exits and returns, from the drive's own phase history.
        let mut shutdowns = 0;
        let mut in4 = false;
        for (t, phase) in &p.phases {
            if *phase == 4 && !in4 {
                if shutdowns > 0 {
                    events.push((*t, RingEventKind::Operating { drive: d.address }));
                }
                in4 = true;
            } else if *phase != 4 && in4 {
                in4 = false;
                shutdowns += 1;
                events.push((
                    *t,
                    RingEventKind::ShutDown {
                        drive: d.address,
                        phase: *phase,
                    },
                ));
            }
        }
        let ds = status.drives.iter().find(|s| s.address.get() == d.address);
        let plan = timing.and_then(|t| t.drives.iter().find(|x| x.address == d.address));
        let axis = p.node.drive().axis();
        drives.push(DriveReport {
            address: d.address,
            position: k + 1,
            idn_file: d.idn_file.as_ref().map(|f| f.display().to_string()),
            telegram_type,
            t1_us: plan.map(|x| x.t1_us()),
            t2_us: timing.map(|t| t.t2_us()),
            t3_us: timing.map(|t| t.t3_us),
            t4_us: timing.map(|t| t.t4_us),
            ats_received: ds.map_or(0, |s| s.ats_received),
            ats_missed: ds.map_or(0, |s| s.ats_missed),
            mdts_missed: p.commands_missing,
            mst_errors: watch.mst_errors.get(k + 1).copied().unwrap_or(0),
            shutdowns,
            phase: p.node.phase().number(),
            powered: ring.sim.powered(k + 1),
            commands_applied: p.commands_applied,
            corrupted_commands: p.corrupted.len() as u64,
            axis: AxisReport {
                velocity_rpm: axis.velocity_rpm(),
                position_deg: axis.position_deg(),
                command: format!("{:?}", axis.command()),
                status_word: p.node.drive().status_word().raw(),
            },
            problems: p.problems.iter().map(|(_, s)| s.clone()).collect(),
        });
    }
    events.sort_by_key(|(t, _)| *t);
    RingReport {
        variant: match spec.variant {
            Variant::Sercon816 => "SERCON816".into(),
            Variant::Sercon410b => "SERCON410B".into(),
        },
        bit_rate_mbit: spec.bit_rate.mbit(),
        cycle_us: spec.cycle_us,
        seed: spec.seed,
        faults: spec.faults.iter().map(|f| f.text.clone()).collect(),
        result: if reached.is_some() {
            RunResult::Phase4
        } else {
            RunResult::NotReached
        },
        phase4_at_s: reached.map(secs),
        sim_time_s: secs(end),
        final_phase: status.phase,
        final_progress: format!("{:?}", status.progress),
        cycles: status.cycles,
        service_requests: status.service_requests,
        restarts: status.restarts,
        ring_delay_us: m.master.ring_delay_us(),
        ring_delay_ns: ring
            .sim
            .ring_delay(0, 0, spec.bit_rate.bit_time())
            .map_or(0, |d| d.as_picos() / 1000),
        timeline: m
            .timeline
            .iter()
            .map(|(t, phase, progress)| MasterEvent {
                t_s: secs(*t),
                phase: *phase,
                progress: format!("{progress:?}"),
            })
            .collect(),
        events: events
            .into_iter()
            .map(|(t, kind)| RingEvent { t_s: secs(t), kind })
            .collect(),
        drives,
        fast_path_collisions: None,
    }
}
