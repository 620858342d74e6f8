//! What a ring run reports: the phase timeline, each drive's address, telegram type,
//! T1–T4, telegram counts, error counters and final axis state, and what happened to the
//! ring (where it was open, which drives lost MSTs and shut down).

use std::fmt::Write as _;

use serde::Serialize;

/// How the run ended.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunResult {
    /// The master reached phase 4 and ran the requested time.
    Phase4,
    /// The master never reached phase 4.
    NotReached,
}

/// The master's phase or progress changed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MasterEvent {
    /// Simulated time, s.
    pub t_s: f64,
    /// Phase sent in the MST.
    pub phase: u8,
    /// Where the phase-up stands (`sercdrv::master::Progress`).
    pub progress: String,
}

/// Something that happened to the ring.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum RingEventKind {
    /// A receiver sees no light; `first_dark` is the first node in ring order that sees
    /// none (410B §4.1 2H.13 FIBBR): the fibre or node before it is at fault.
    Open {
        /// "drive N" or "master".
        first_dark: String,
    },
    /// Every powered receiver sees light again.
    Closed,
    /// A drive lost power.
    PowerOff {
        /// Its address.
        drive: u8,
    },
    /// A drive has power again.
    PowerOn {
        /// Its address.
        drive: u8,
    },
    /// A drive's MST error counter rose (410B §4.2 word 10 NMSTERR).
    LostMsts {
        /// Its address.
        drive: u8,
    },
    /// A drive left phase 4: its axis no longer follows commands.
    ShutDown {
        /// Its address.
        drive: u8,
        /// The phase it went to.
        phase: u8,
    },
    /// A drive is back in phase 4.
    Operating {
        /// Its address.
        drive: u8,
    },
    /// The master reported an error.
    MasterError {
        /// The error's text (names drive, phase, IDN where they apply).
        text: String,
    },
}

/// A ring event at a time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RingEvent {
    /// Simulated time, s.
    pub t_s: f64,
    /// What.
    #[serde(flatten)]
    pub kind: RingEventKind,
}

/// An axis at the end of the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxisReport {
    /// Velocity, rpm.
    pub velocity_rpm: f64,
    /// Position, degrees.
    pub position_deg: f64,
    /// What it follows (`Coast`, `Halt`, `Velocity(rpm)`, `Position(deg)`).
    pub command: String,
    /// The drive's status word (without the service-channel bits).
    pub status_word: u16,
}

/// One drive.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DriveReport {
    /// SERCOS address.
    pub address: u8,
    /// Ring position (1 = first after the master).
    pub position: usize,
    /// Its IDN file, if not the standard catalogue.
    pub idn_file: Option<String>,
    /// S-0-0015, telegram type.
    pub telegram_type: u16,
    /// S-0-0006, AT transmission starting time T1, µs.
    pub t1_us: Option<u32>,
    /// S-0-0089, MDT transmission starting time T2, µs.
    pub t2_us: Option<u32>,
    /// S-0-0008, command value valid time T3, µs.
    pub t3_us: Option<u32>,
    /// S-0-0007, feedback acquisition capture point T4, µs.
    pub t4_us: Option<u32>,
    /// ATs the master received without error in phases 3-4.
    pub ats_received: u64,
    /// ATs missing or in error in phases 3-4.
    pub ats_missed: u64,
    /// Phase 3-4 cycles without a valid MDT record at the drive.
    pub mdts_missed: u64,
    /// MSTs the drive missed (410B §4.2 word 10 NMSTERR, summed over power cycles).
    pub mst_errors: u64,
    /// Times it left phase 4.
    pub shutdowns: u32,
    /// Its phase at the end.
    pub phase: u8,
    /// Powered at the end.
    pub powered: bool,
    /// Velocity commands it applied (changes of S-0-0036).
    pub commands_applied: u64,
    /// Applied velocity commands the master never sent (corrupted values).
    pub corrupted_commands: u64,
    /// The axis at the end.
    pub axis: AxisReport,
    /// Refusals and failures its slave driver reported.
    pub problems: Vec<String>,
}

/// The whole run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RingReport {
    /// `SERCON816` or `SERCON410B`.
    pub variant: String,
    /// Bit rate, Mbit/s.
    pub bit_rate_mbit: u32,
    /// tScyc, µs.
    pub cycle_us: u32,
    /// Seed.
    pub seed: u64,
    /// The faults, as given.
    pub faults: Vec<String>,
    /// How the run ended.
    pub result: RunResult,
    /// When the master first reached phase 4, s.
    pub phase4_at_s: Option<f64>,
    /// Simulated time at the end, s.
    pub sim_time_s: f64,
    /// The master's phase at the end.
    pub final_phase: u8,
    /// The master's progress at the end.
    pub final_progress: String,
    /// Cycles the master counted.
    pub cycles: u64,
    /// Service-channel requests the master completed.
    pub service_requests: u64,
    /// Times the master fell back to phase 0.
    pub restarts: u32,
    /// Ring delay the master measured, µs (TCYCDEL, 410B §4.1 11H).
    pub ring_delay_us: u16,
    /// The ring's delay as simulated, ns: every fibre plus every drive's repeater latency,
    /// from the master's transmitter back to its receiver (what TCYCDEL measures in whole
    /// µs, so a short ring reads 0).
    pub ring_delay_ns: u64,
    /// The master's phase timeline.
    pub timeline: Vec<MasterEvent>,
    /// What happened to the ring, in time order.
    pub events: Vec<RingEvent>,
    /// Every drive, in ring order.
    pub drives: Vec<DriveReport>,
    /// Set when the run on the simulator's fast path had telegrams meet at a repeater's
    /// output where the fast path cannot follow the chips (that many): the report is then
    /// the reference path's run of the same ring (spec-notes "Repeater collisions").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fast_path_collisions: Option<u64>,
}

impl RingReport {
    /// The report as a SERCOS engineer reads it.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let _ = self.write_text(&mut s);
        s
    }

    fn write_text(&self, s: &mut String) -> std::fmt::Result {
        writeln!(
            s,
            "ring: {} master + {} drives, {} Mbit/s, cycle {} µs, seed {}",
            self.variant,
            self.drives.len(),
            self.bit_rate_mbit,
            self.cycle_us,
            self.seed
        )?;
        for f in &self.faults {
            writeln!(s, "fault: {f}")?;
        }
        if let Some(n) = self.fast_path_collisions {
            writeln!(
                s,
                "telegrams met at repeaters {n} times on the simulator's fast path: this is the reference path's run"
            )?;
        }
        writeln!(s, "\nphase timeline (master)")?;
        for e in &self.timeline {
            writeln!(s, "  {:>10.6} s  phase {}  {}", e.t_s, e.phase, e.progress)?;
        }
        if !self.events.is_empty() {
            writeln!(s, "\nring events")?;
            for e in &self.events {
                writeln!(s, "  {:>10.6} s  {}", e.t_s, event_text(&e.kind))?;
            }
        }
        writeln!(s, "\ndrives")?;
        writeln!(
            s,
            "  {:>4} {:>3} {:>4} {:>6} {:>6} {:>6} {:>6} {:>8} {:>7} {:>7} {:>7} {:>5} {:>5}  axis",
            "addr",
            "pos",
            "type",
            "T1 µs",
            "T2 µs",
            "T3 µs",
            "T4 µs",
            "AT ok",
            "AT miss",
            "MDT mis",
            "MST err",
            "phase",
            "shut"
        )?;
        let opt = |v: Option<u32>| v.map_or_else(|| "-".to_string(), |v| v.to_string());
        for d in &self.drives {
            writeln!(
                s,
                "  {:>4} {:>3} {:>4} {:>6} {:>6} {:>6} {:>6} {:>8} {:>7} {:>7} {:>7} {:>5} {:>5}  {:.1} rpm, {:.1}°, {}{}",
                d.address,
                d.position,
                d.telegram_type,
                opt(d.t1_us),
                opt(d.t2_us),
                opt(d.t3_us),
                opt(d.t4_us),
                d.ats_received,
                d.ats_missed,
                d.mdts_missed,
                d.mst_errors,
                d.phase,
                d.shutdowns,
                d.axis.velocity_rpm,
                d.axis.position_deg,
                d.axis.command,
                if d.powered { "" } else { " (no power)" }
            )?;
            if d.corrupted_commands > 0 {
                writeln!(
                    s,
                    "       drive {} applied {} command values the master never sent",
                    d.address, d.corrupted_commands
                )?;
            }
            for p in &d.problems {
                writeln!(s, "       drive {}: {p}", d.address)?;
            }
        }
        writeln!(
            s,
            "\nmaster: phase {} ({}), {} cycles, {} service requests, {} restarts, ring delay {} µs (TCYCDEL; fibres and repeaters {:.3} µs)",
            self.final_phase,
            self.final_progress,
            self.cycles,
            self.service_requests,
            self.restarts,
            self.ring_delay_us,
            self.ring_delay_ns as f64 / 1000.0
        )?;
        match (&self.result, self.phase4_at_s) {
            (RunResult::Phase4, Some(t)) => writeln!(
                s,
                "result: phase 4 reached at {t:.6} s, ran to {:.6} s",
                self.sim_time_s
            ),
            _ => writeln!(
                s,
                "result: the ring did not reach phase 4 within {:.6} s",
                self.sim_time_s
            ),
        }
    }
}

fn event_text(k: &RingEventKind) -> String {
    match k {
        RingEventKind::Open { first_dark } => {
            format!("ring open: {first_dark} is the first node that sees no light")
        }
        RingEventKind::Closed => "ring closed: every receiver sees light".into(),
        RingEventKind::PowerOff { drive } => format!("drive {drive} powered off"),
        RingEventKind::PowerOn { drive } => format!("drive {drive} powered on"),
        RingEventKind::LostMsts { drive } => format!("drive {drive} lost MSTs"),
        RingEventKind::ShutDown { drive, phase } => {
            format!("drive {drive} shut down (left phase 4 for phase {phase})")
        }
        RingEventKind::Operating { drive } => format!("drive {drive} back in phase 4"),
        RingEventKind::MasterError { text } => format!("master: {text}"),
    }
}
