//! Shared helpers of the ring and fault tests: building static rings, reading the telegram
//! log back, reading headers.
#![allow(dead_code)]

use sercon_model::Chip;
use sercon_regs::ram::header::RxHeader;
use sercon_regs::{SerconBus, Variant};
use sercos_sim::recorder::TraceOutput;
use sercos_sim::static_ring::{RingPlan, StaticRing};
use sercos_sim::trace::LogFormat;
use sercos_sim::{HostProgram, SimConfig, Simulation, Wake};
use sercos_wire::time::{Duration, Instant};

/// One line of the text log.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Line {
    pub ps: u64,
    pub seg: u16,
    pub master: bool,
    pub kind: String,
    pub adr: Option<u8>,
    pub ok: bool,
}

/// Parses the text telegram log ("0.000006000000 seg 0 master MST adr 255 …").
pub fn parse_log(log: &[u8]) -> Vec<Line> {
    let text = String::from_utf8_lossy(log);
    text.lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let (secs, frac) = f.first()?.split_once('.')?;
            let ps = secs.parse::<u64>().ok()? * 1_000_000_000_000 + frac.parse::<u64>().ok()?;
            let seg = f.get(2)?.parse().ok()?;
            let master = *f.get(3)? == "master";
            let kind = f.get(4)?.to_string();
            let adr = f
                .iter()
                .position(|w| *w == "adr")
                .and_then(|i| f.get(i + 1))
                .and_then(|a| a.parse().ok());
            let ok = l.ends_with("fcs ok");
            Some(Line {
                ps,
                seg,
                master,
                kind,
                adr,
                ok,
            })
        })
        .collect()
}

/// `n` µs after time 0.
pub fn us(n: u64) -> Instant {
    Instant::ZERO + Duration::from_micros(n)
}

/// Builds a static ring with a text log on every segment.
pub fn build(ring: &StaticRing) -> (SimConfig, Vec<Box<dyn sercos_sim::HostProgram>>, RingPlan) {
    let (mut cfg, hosts, plan) = ring.build().expect("the ring fits");
    cfg.traces.log = Some(LogFormat::Text);
    (cfg, hosts, plan)
}

/// Runs to `until` and returns the simulation and its traces.
pub fn run(
    cfg: SimConfig,
    hosts: Vec<Box<dyn sercos_sim::HostProgram>>,
    until: Instant,
) -> (Simulation, TraceOutput) {
    let mut sim = Simulation::new(cfg, hosts).expect("valid configuration");
    sim.run_until(until).expect("runs");
    let out = sim.finish().expect("traces");
    (sim, out)
}

/// The receive header at `at` of `chip`.
pub fn rx_header(chip: &mut Chip, at: u16) -> RxHeader {
    let w: Vec<u16> = (0..5).map(|i| chip.read_ram(at + i)).collect();
    RxHeader::decode(Variant::Sercon816, &w).expect("a receive header")
}

/// `n` RAM words from `at`.
pub fn words(chip: &mut Chip, at: u16, n: u16) -> Vec<u16> {
    (0..n).map(|i| chip.read_ram(at + i)).collect()
}

/// A static ring's host that, from its first deadline on, reads `accesses` RAM words every
/// `period` (0 accesses: the same wakes, an idle bus).
pub struct ReadingHost {
    /// The static ring's own host (it lays out the RAM at the start).
    pub inner: Box<dyn HostProgram>,
    /// Time between two busy spells.
    pub period: Duration,
    /// RAM words read per spell (100 ns each at the default bus cost).
    pub accesses: u16,
}

impl HostProgram for ReadingHost {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        match why {
            Wake::Start | Wake::PowerOn => {
                self.inner.wake(bus, now, why);
                Some(now.saturating_add(self.period))
            }
            Wake::Deadline => {
                for a in 0..self.accesses {
                    let _ = bus.read_ram(a);
                }
                Some(now.saturating_add(self.period))
            }
            Wake::Interrupt { .. } => None,
        }
    }
}

/// Each of a static ring's `hosts` wrapped in a [`ReadingHost`] reading `accesses` words
/// every `period`.
pub fn reading_hosts(
    hosts: Vec<Box<dyn HostProgram>>,
    period: Duration,
    accesses: u16,
) -> Vec<Box<dyn HostProgram>> {
    hosts
        .into_iter()
        .map(|inner| {
            Box::new(ReadingHost {
                inner,
                period,
                accesses,
            }) as Box<dyn HostProgram>
        })
        .collect()
}

/// Every node's registers (0H–3FH) then RAM (2048 words), node 0 the master, as the fast path
/// and the reference path are compared: a slave's 3H.15 REACTN left out (the fast path gives
/// slaves no other slave's AT; spec-notes "Fast path = reference path", limit).
pub fn node_states(sim: &mut Simulation, slaves: usize) -> Vec<Vec<u16>> {
    (0..=slaves)
        .map(|i| {
            let Some(c) = sim.chip_mut(i) else {
                return Vec::new();
            };
            let mut w: Vec<u16> = (0u8..0x40).map(|a| c.read_register(a)).collect();
            if i > 0 {
                w[3] &= !(1 << 15);
            }
            w.extend((0..2048).map(|a| c.read_ram(a)));
            w
        })
        .collect()
}
