//! From a [`RingSpec`] to a [`Simulation`]: the master on node 0, one emulated drive per
//! [`DriveSpec`](super::DriveSpec) in ring order, fibres of the given lengths, faults placed
//! in simulated time, traces switched on.

use std::cell::RefCell;
use std::rc::Rc;

use sercdrv::master::{Master, MasterConfig};
use sercdrv::slave::SlaveConfig;
use sercon_model::ChipConfig;
use sercon_model::pins::{Pin, PinSet};
use sercon_regs::Variant;
use sercos_drive::config_file;
use sercos_drive::database::IdnDatabase;
use sercos_drive::node::DriveNode;
use sercos_sim::config::CaptureFormat;
use sercos_sim::trace::{LogFormat, SegmentId};
use sercos_sim::{
    Delivery, Fault, FaultKind, Fibre, HostProgram, NodeConfig, SimConfig, Simulation, Topology,
    TraceConfig,
};
use sercos_wire::address::DriveAddress;
use sercos_wire::time::{BitRate, Instant};

use super::error::RingError;
use super::fault_spec::{FaultWhat, NodeRef};
use super::probes::{DriveProbe, MasterProbe, Shared};
use super::spec::RingSpec;

/// Pins written to the VCD of every node: the interrupts, the cycle clock and the line.
const VCD_PINS: [Pin; 4] = [Pin::Int0, Pin::Int1, Pin::ConClk, Pin::TxD];

/// A ring ready to run: the simulation and handles on the master and the drives.
pub struct BuiltRing {
    /// The simulation.
    pub sim: Simulation,
    /// The master and its history.
    pub master: Rc<RefCell<MasterProbe>>,
    /// The drives in ring order, with their histories.
    pub drives: Vec<Rc<RefCell<DriveProbe>>>,
}

/// The chip of `variant` as the boards of the ring have it (816: MCLK 32 MHz; 410B: 20 MHz
/// with SREGEN = 1; SCLK 64 MHz).
fn chip(variant: Variant) -> ChipConfig {
    match variant {
        Variant::Sercon816 => ChipConfig::sercon816(),
        Variant::Sercon410b => ChipConfig::sercon410b(),
    }
}

/// Checks what the parts below would refuse with a less clear message.
pub(super) fn validate(spec: &RingSpec) -> Result<(), RingError> {
    let bad = |m: String| Err(RingError::Spec(m));
    if spec.drives.is_empty() {
        return bad("a ring needs at least one drive".into());
    }
    if spec.drives.len() > sercdrv::master::MAX_DRIVES {
        return bad(format!(
            "{} drives: the master serves at most {} (one service container each, 410B §4.2 SCPT0-7)",
            spec.drives.len(),
            sercdrv::master::MAX_DRIVES
        ));
    }
    for (i, d) in spec.drives.iter().enumerate() {
        if !(1..=254).contains(&d.address) {
            return bad(format!("drive address {} is not 1-254", d.address));
        }
        if spec.drives[..i].iter().any(|e| e.address == d.address) {
            return bad(format!("drive address {} appears twice", d.address));
        }
    }
    // 410B §4.1 1H: the SERCON410B runs at 2 or 4 Mbit/s; 8 and 16 are the 816's (816 §2.3.1).
    if spec.variant == Variant::Sercon410b
        && matches!(spec.bit_rate, BitRate::Mbit8 | BitRate::Mbit16)
    {
        return bad(format!(
            "the SERCON410B runs at 2 or 4 Mbit/s, not {}",
            spec.bit_rate.mbit()
        ));
    }
    // sercos-facts.md: tScyc from 62.5 µs; TSCYC0/1 hold it in µs (410B §4.1 0FH/10H).
    if !(62..=65_000).contains(&spec.cycle_us) {
        return bad(format!(
            "cycle time {} µs is not 62-65000 µs",
            spec.cycle_us
        ));
    }
    let fibres = spec.drives.len() + 1;
    for (what, segment) in [
        ("--log-segment", spec.traces.log_segment),
        ("--pcap-segment", spec.traces.pcap_segment),
    ] {
        if let Some(s) = segment
            && s >= fibres
        {
            return bad(format!(
                "{what} {s}: the ring has fibres 0-{} (fibre k runs from node k to node k + 1)",
                fibres - 1
            ));
        }
    }
    let t = &spec.traces;
    if t.vcd.is_none() && (t.vcd_pins.is_some() || t.vcd_nodes.is_some()) {
        return bad(
            "--vcd-pins and --vcd-nodes (vcd_pins, vcd_nodes) choose what the VCD holds: give --vcd FILE (vcd = \"FILE\" under [traces]) too".into(),
        );
    }
    if t.vcd_pins.as_ref().is_some_and(|p| p.is_empty()) {
        return bad(format!("--vcd-pins names no pin (pins: {})", pin_names()));
    }
    if t.vcd_nodes.as_ref().is_some_and(|n| n.is_empty()) {
        return bad("--vcd-nodes names no node (\"master\" or drive addresses)".into());
    }
    for node in t.vcd_nodes.iter().flatten() {
        if let Err(RingError::Spec(why)) = node_index(spec, *node) {
            return bad(format!("--vcd-nodes: {why}"));
        }
    }
    for f in &spec.faults {
        for node in fault_nodes(&f.what) {
            if let NodeRef::Drive(a) = node
                && spec.position_of(a).is_none()
            {
                return bad(format!(
                    "fault {:?}: there is no drive {a} on the ring",
                    f.text
                ));
            }
        }
    }
    Ok(())
}

/// The pins a VCD can hold, by their datasheet names (410B §2, 816 §2).
pub fn pin_names() -> String {
    Pin::ALL.map(Pin::name).join(", ")
}

/// The pin of datasheet name `text` (case and `_` free, [`Pin::from_name`]), or why not with
/// the names there are: `--vcd-pins` and a ring file's `vcd_pins` say the same.
pub fn pin_named(text: &str) -> Result<Pin, String> {
    Pin::from_name(text.trim())
        .ok_or_else(|| format!("{text:?} is no pin of the chip (pins: {})", pin_names()))
}

fn fault_nodes(what: &FaultWhat) -> Vec<NodeRef> {
    match *what {
        FaultWhat::Break { into }
        | FaultWhat::Burst { into, .. }
        | FaultWhat::Distortion { into } => vec![into],
        FaultWhat::BitErrors { into, .. } => into.into_iter().collect(),
        FaultWhat::Power { node } | FaultWhat::Drift { node, .. } => vec![node],
    }
}

/// Node index of `node` (0 the master, drives from 1 in ring order).
fn node_index(spec: &RingSpec, node: NodeRef) -> Result<usize, RingError> {
    match node {
        NodeRef::Master => Ok(0),
        NodeRef::Drive(a) => spec
            .position_of(a)
            .ok_or_else(|| RingError::Spec(format!("there is no drive {a} on the ring"))),
    }
}

/// Segment (fibre) feeding `node`'s receiver: fibre k runs from node k to node k + 1, the
/// last one back to the master (sercos_sim::Topology::Ring).
fn segment_into(spec: &RingSpec, node: NodeRef) -> Result<usize, RingError> {
    let n = spec.drives.len() + 1;
    let i = node_index(spec, node)?;
    Ok((i + n - 1) % n)
}

/// The simulator's faults for `spec`, with phase-4 time 0 at `origin`; open-ended faults
/// end at `end`.
pub(super) fn sim_faults(
    spec: &RingSpec,
    origin: Instant,
    end: Instant,
) -> Result<Vec<Fault>, RingError> {
    let at = |d| origin.saturating_add(d);
    let mut out = Vec::new();
    for f in &spec.faults {
        let from = at(f.from);
        let until = f.until.map(at);
        let segments = |into: Option<NodeRef>| -> Result<Vec<usize>, RingError> {
            match into {
                Some(n) => Ok(vec![segment_into(spec, n)?]),
                None => Ok((0..=spec.drives.len()).collect()),
            }
        };
        match f.what {
            FaultWhat::Break { into } => out.push(Fault {
                at: from,
                kind: FaultKind::FibreBreak {
                    segment: segment_into(spec, into)?,
                    until,
                },
            }),
            FaultWhat::BitErrors { into, rate } => {
                for segment in segments(into)? {
                    out.push(Fault {
                        at: from,
                        kind: FaultKind::BitErrors {
                            segment,
                            until: until.unwrap_or(end),
                            rate,
                        },
                    });
                }
            }
            FaultWhat::Burst { into, bits } => out.push(Fault {
                at: from,
                kind: FaultKind::BitErrorBurst {
                    segment: segment_into(spec, into)?,
                    bits,
                },
            }),
            FaultWhat::Power { node } => out.push(Fault {
                at: from,
                kind: FaultKind::PowerOff {
                    node: node_index(spec, node)?,
                    until,
                },
            }),
            FaultWhat::Drift { node, ppm } => out.push(Fault {
                at: from,
                kind: FaultKind::ClockDrift {
                    node: node_index(spec, node)?,
                    ppm,
                },
            }),
            FaultWhat::Distortion { into } => out.push(Fault {
                at: from,
                kind: FaultKind::Distortion {
                    segment: segment_into(spec, into)?,
                    until: until.unwrap_or(end),
                },
            }),
        }
    }
    Ok(out)
}

/// The trace segment of fibre `i`.
fn segment_id(i: usize) -> SegmentId {
    SegmentId(u16::try_from(i).unwrap_or(u16::MAX))
}

/// The traces the simulator keeps for `spec`'s trace files.
fn trace_config(spec: &RingSpec, nodes: usize) -> TraceConfig {
    let t = &spec.traces;
    let json = t
        .log
        .as_ref()
        .and_then(|p| p.extension())
        .is_some_and(|e| e == "jsonl" || e == "json");
    let log = if t.transcript.is_some() || json {
        Some(LogFormat::JsonLines)
    } else if t.log.is_some() {
        Some(LogFormat::Text)
    } else {
        None
    };
    // The transcript reads the master's telegrams on segment 0 (master → first drive); a
    // log of every segment holds them too.
    let log_segment = t.log_segment.map(segment_id);
    let vcd = if t.vcd.is_some() {
        let pins = PinSet::of(t.vcd_pins.as_deref().unwrap_or(&VCD_PINS));
        match &t.vcd_nodes {
            None => (0..nodes).map(|i| (i, pins)).collect(),
            // In ring order, each node once, whatever order the user named them in (the
            // VCD's scopes follow the ring); `validate` found every drive named.
            Some(named) => {
                let mut chosen: Vec<usize> = named
                    .iter()
                    .filter_map(|n| node_index(spec, *n).ok())
                    .collect();
                chosen.sort_unstable();
                chosen.dedup();
                chosen.into_iter().map(|i| (i, pins)).collect()
            }
        }
    } else {
        Vec::new()
    };
    TraceConfig {
        log,
        log_segment,
        capture: t.pcap.as_ref().map(|_| {
            (
                segment_id(t.pcap_segment.unwrap_or(nodes.saturating_sub(1))),
                CaptureFormat::Pcap,
            )
        }),
        vcd,
        hash: false,
    }
}

/// Loads the IDN database of every drive (the standard catalogue where no file is given).
pub fn databases(spec: &RingSpec) -> Result<Vec<IdnDatabase>, RingError> {
    spec.drives
        .iter()
        .map(|d| match &d.idn_file {
            Some(path) => config_file::load(path).map_err(RingError::IdnFile),
            None => Ok(IdnDatabase::standard()),
        })
        .collect()
}

/// The master's configuration for `spec`'s ring: its drives in ring order and the telegram
/// type; a type above 7 is refused.
pub fn master_config(spec: &RingSpec) -> Result<MasterConfig, RingError> {
    let addresses: Vec<DriveAddress> = spec
        .drives
        .iter()
        .filter_map(|d| DriveAddress::new(d.address))
        .collect();
    let mut cfg = MasterConfig::new(spec.variant, spec.bit_rate, spec.cycle_us, addresses);
    // sercos-facts.md S-0-0015: 0-6 standard, 7 configured.
    if !cfg.set_telegram_type(spec.telegram_type) {
        return Err(RingError::Spec(format!(
            "telegram type {} is not 0-7 (S-0-0015)",
            spec.telegram_type
        )));
    }
    Ok(cfg)
}

/// Builds the ring of `spec` with `faults` (already in simulated time), traces on or off.
pub fn build(spec: &RingSpec, faults: Vec<Fault>, traces: bool) -> Result<BuiltRing, RingError> {
    validate(spec)?;
    let databases = databases(spec)?;
    let master = Master::new(master_config(spec)?).map_err(RingError::Master)?;
    let master = Rc::new(RefCell::new(MasterProbe::new(master)));
    let mut nodes = vec![NodeConfig::new("master", chip(spec.variant))];
    let mut hosts: Vec<Box<dyn HostProgram>> = vec![Box::new(Shared(master.clone()))];
    let mut drives = Vec::new();
    for (d, db) in spec.drives.iter().zip(databases) {
        // The ring's bit rate and phase 0-2 cycle are set on every drive (docs/spec-notes.md,
        // "The ring command": the switches on the drives match the master's).
        let mut sc = SlaveConfig::new(spec.variant, d.address);
        sc.bit_rate = spec.bit_rate;
        sc.noncyclic_cycle_us = spec.cycle_us;
        let node = DriveNode::with_config(sc, db).map_err(|source| RingError::Drive {
            address: d.address,
            source,
        })?;
        let probe = Rc::new(RefCell::new(DriveProbe::new(node)));
        nodes.push(NodeConfig::new(
            &format!("drive{}", d.address),
            chip(spec.variant),
        ));
        hosts.push(Box::new(Shared(probe.clone())));
        drives.push(probe);
    }
    let mut fibres: Vec<Fibre> = spec
        .drives
        .iter()
        .map(|d| Fibre::metres(d.fibre_m))
        .collect();
    fibres.push(Fibre::metres(spec.return_fibre_m));
    let n = nodes.len();
    let sim_cfg = SimConfig {
        topology: Topology::Ring { fibres },
        nodes,
        faults,
        seed: spec.seed,
        delivery: if spec.reference {
            Delivery::Exact
        } else {
            Delivery::Fast
        },
        traces: if traces {
            trace_config(spec, n)
        } else {
            TraceConfig::default()
        },
    };
    let sim = Simulation::new(sim_cfg, hosts).map_err(RingError::Sim)?;
    Ok(BuiltRing {
        sim,
        master,
        drives,
    })
}
