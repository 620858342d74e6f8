//! A simulated ring (sercos-sim) of a `sercdrv::master::Master` and emulated drives
//! (`sercos_drive::node::DriveNode`), with the master's telegrams taken from the simulator's
//! JSON-lines log of segment 0 (master → slave 1) and turned into the service-channel
//! transcript of `sercon capture transcript` (sercos_wire::service_transcript).
#![allow(dead_code)]

use std::cell::RefCell;
use std::rc::Rc;

use sercdrv::master::{Master, MasterConfig, Progress};
use sercon_model::ChipConfig;
use sercon_regs::SerconBus;
use sercon_regs::Variant;
use sercos_drive::database::IdnDatabase;
use sercos_drive::node::DriveNode;
use sercos_sim::trace::{LogFormat, SegmentId};
use sercos_sim::{
    Fault, HostProgram, NodeConfig, SimConfig, Simulation, Topology, TraceConfig, Wake,
};
use sercos_wire::service_transcript::{TranscriptBuilder, TranscriptEntry};
use sercos_wire::time::{BitRate, Duration, Instant};

/// Runs a `sercon_regs::host::HostProgram` as a simulator host program, shared so the test
/// can look at it between runs.
pub struct Shared<P>(pub Rc<RefCell<P>>);

impl<P: HostProgram> HostProgram for Shared<P> {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        self.0.borrow_mut().wake(bus, now, why)
    }
}

/// The chip of `variant` as the boards of the tests have it (816: MCLK 32 MHz, 410B:
/// 20 MHz with SREGEN = 1; SCLK 64 MHz).
pub fn chip(variant: Variant) -> ChipConfig {
    match variant {
        Variant::Sercon816 => ChipConfig::sercon816(),
        Variant::Sercon410b => ChipConfig::sercon410b(),
    }
}

/// A master and its drives on a simulated fibre ring.
pub struct Ring {
    pub sim: Simulation,
    pub master: Rc<RefCell<Master>>,
    pub drives: Vec<Rc<RefCell<DriveNode>>>,
    pub cycle: Duration,
}

/// The drives' databases: the emulated drive's standard set.
pub fn standard_drives(n: usize) -> Vec<IdnDatabase> {
    (0..n).map(|_| IdnDatabase::standard()).collect()
}

/// Builds the ring for `cfg` with one emulated drive per configured address, each with its
/// database, the master's segment logged as JSON lines, and `faults`.
pub fn ring(cfg: MasterConfig, databases: Vec<IdnDatabase>, faults: Vec<Fault>) -> Ring {
    ring_with(cfg, databases, faults, sercos_sim::Delivery::Fast)
}

/// [`ring`] with the simulator's `delivery` (fast hops or every bit on every fibre).
pub fn ring_with(
    cfg: MasterConfig,
    databases: Vec<IdnDatabase>,
    faults: Vec<Fault>,
    delivery: sercos_sim::Delivery,
) -> Ring {
    ring_wrapped(cfg, databases, faults, delivery, |_, host| host)
}

/// [`ring_with`] with every node's host program passed through `wrap` (node 0 the master,
/// then the drives in ring order): a host between a driver and its chip, e.g. one that
/// garbles what the driver reads.
pub fn ring_wrapped(
    cfg: MasterConfig,
    databases: Vec<IdnDatabase>,
    faults: Vec<Fault>,
    delivery: sercos_sim::Delivery,
    mut wrap: impl FnMut(usize, Box<dyn HostProgram>) -> Box<dyn HostProgram>,
) -> Ring {
    let variant = cfg.variant;
    let cycle = Duration::from_micros(u64::from(cfg.cycle_us));
    let mut nodes = vec![NodeConfig::new("master", chip(variant))];
    let mut hosts: Vec<Box<dyn HostProgram>> = Vec::new();
    let mut drives = Vec::new();
    let bit_rate = cfg.bit_rate;
    let cycle_us = cfg.cycle_us;
    let addresses: Vec<u8> = cfg.drives.iter().map(|d| d.get()).collect();
    let master = Rc::new(RefCell::new(
        Master::new(cfg).expect("a valid master config"),
    ));
    hosts.push(wrap(0, Box::new(Shared(master.clone()))));
    for (address, db) in addresses.iter().zip(databases) {
        nodes.push(NodeConfig::new(&format!("drive{address}"), chip(variant)));
        let mut sc = sercdrv::slave::SlaveConfig::new(variant, *address);
        sc.bit_rate = bit_rate;
        sc.noncyclic_cycle_us = cycle_us;
        let node = Rc::new(RefCell::new(
            DriveNode::with_config(sc, db).expect("a valid drive"),
        ));
        hosts.push(wrap(hosts.len(), Box::new(Shared(node.clone()))));
        drives.push(node);
    }
    let n = nodes.len();
    let sim_cfg = SimConfig {
        topology: Topology::ring(n, 10),
        nodes,
        faults,
        seed: 1,
        delivery,
        traces: TraceConfig {
            log: Some(LogFormat::JsonLines),
            log_segment: Some(SegmentId(0)),
            ..TraceConfig::default()
        },
    };
    let sim = Simulation::new(sim_cfg, hosts).expect("a valid simulation");
    Ring {
        sim,
        master,
        drives,
        cycle,
    }
}

impl Ring {
    /// Runs until the master reaches `phase` (or halts), at most `max_cycles` cycles;
    /// returns the cycles it took.
    pub fn run_to_phase(&mut self, phase: u8, max_cycles: u64) -> Option<u64> {
        for c in 0..max_cycles {
            let t = self.sim.now().saturating_add(self.cycle);
            self.sim.run_until(t).expect("the simulation runs");
            let m = self.master.borrow();
            if m.phase() == phase && m.progress() != Progress::Halted {
                return Some(c + 1);
            }
            if m.progress() == Progress::Halted {
                return None;
            }
        }
        None
    }

    /// Runs `cycles` more cycles.
    pub fn run_cycles(&mut self, cycles: u64) {
        let t = self
            .sim
            .now()
            .saturating_add(self.cycle.saturating_mul(cycles));
        self.sim.run_until(t).expect("the simulation runs");
    }

    /// The master's telegrams on segment 0 so far (ADR and data, FCS checked), in order.
    pub fn master_telegrams(&mut self) -> Vec<Vec<u8>> {
        let out = self.sim.finish().expect("traces");
        master_telegrams(&out.log)
    }
}

/// The telegrams the master sent, from a JSON-lines log of its segment.
pub fn master_telegrams(log: &[u8]) -> Vec<Vec<u8>> {
    let text = String::from_utf8_lossy(log);
    let mut out = Vec::new();
    for line in text.lines() {
        let Ok(v) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        if v["origin"] != "master" || v["fcs"] != "ok" {
            continue;
        }
        let Some(hex) = v["bytes"].as_str() else {
            continue;
        };
        let bytes: Vec<u8> = (0..hex.len() / 2)
            .filter_map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).ok())
            .collect();
        out.push(bytes);
    }
    out
}

/// The service-channel transcript of the master's telegrams (`sercon capture transcript`).
pub fn transcript(telegrams: &[Vec<u8>]) -> Vec<TranscriptEntry> {
    let mut b = TranscriptBuilder::new();
    for (i, t) in telegrams.iter().enumerate() {
        b.master_telegram(t, i as u64);
    }
    b.finish()
}

/// (phase, drive, IDN) of every write in a transcript, in order.
pub fn writes(entries: &[TranscriptEntry]) -> Vec<(u8, u8, String)> {
    entries
        .iter()
        .filter(|e| e.op == sercos_wire::service_transcript::ServiceOp::Write)
        .map(|e| {
            (
                e.phase,
                e.drive,
                e.idn.map(|i| i.to_string()).unwrap_or_default(),
            )
        })
        .collect()
}

/// A bit rate and cycle pair used by the tests.
pub fn rate(mbit: u32) -> BitRate {
    BitRate::from_mbit(mbit).expect("a SERCOS bit rate")
}

/// One transcript entry as a line of `sercon capture transcript --json` (fields phase,
/// drive, op, idn, element, words when written, steps, complete, telegram).
pub fn json_line(e: &TranscriptEntry) -> String {
    use sercos_wire::service_transcript::ServiceOp;
    let op = match e.op {
        ServiceOp::Read => "read",
        ServiceOp::Write => "write",
        ServiceOp::Open => "open",
    };
    let mut v = serde_json::json!({
        "phase": e.phase,
        "drive": e.drive,
        "op": op,
        "idn": e.idn.map(|i| i.to_string()),
        "element": e.element.bits(),
        "steps": e.steps,
        "complete": e.complete,
        "telegram": e.first_telegram,
    });
    if !e.words.is_empty() {
        v["words"] = serde_json::json!(e.words);
    }
    v.to_string()
}

/// A transcript as JSON lines.
pub fn json_lines(entries: &[TranscriptEntry]) -> Vec<String> {
    entries.iter().map(json_line).collect()
}

/// The folder of the real captures (`../shared/captures/` beside the repository).
pub fn captures_dir() -> Option<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/captures");
    dir.is_dir().then_some(dir)
}

/// The service transcripts of both captures, decoded as `sercon capture transcript` does
/// (NRZI, every telegram with a valid FCS through the transcript builder); `None` when the
/// captures are not there.
pub fn capture_transcripts() -> Option<Vec<(String, Vec<TranscriptEntry>)>> {
    use sercos_wire::line::{self, CaptureFile, Coding, LineConfig, OwnedDecoded, Polarity};
    let dir = captures_dir()?;
    let mut out = Vec::new();
    for name in ["tc2000r-phaseup.nrzi", "tc2000r-phaseup-2.nrzi"] {
        let bytes = std::fs::read(dir.join(name)).ok()?;
        let file = CaptureFile::parse(&bytes).expect("a capture file");
        let frames = line::decode_all(
            file.bits,
            LineConfig::new(Coding::Nrzi, Polarity::LightOnLow),
        );
        let mut b = TranscriptBuilder::new();
        for (i, f) in frames.iter().enumerate() {
            if let OwnedDecoded::Telegram { bytes, .. } = f {
                b.master_telegram(bytes, i as u64);
            }
        }
        out.push((name.to_string(), b.finish()));
    }
    Some(out)
}

impl Ring {
    /// Runs the simulation up to `t`.
    pub fn run_until(&mut self, t: Instant) {
        self.sim.run_until(t).expect("the simulation runs");
    }
}
