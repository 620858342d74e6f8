//! What a simulation run is made of: topology, nodes, faults, seed, traces.

use sercon_model::ChipConfig;
use sercon_model::pins::PinSet;
use sercos_wire::time::Duration;

use crate::fault::Fault;
use crate::topology::Topology;
use crate::trace::{LogFormat, SegmentId};

/// One node: a controller and the program on its host processor (the program is handed to
/// [`crate::sim::Simulation::new`] separately).
#[derive(Debug, Clone, PartialEq)]
pub struct NodeConfig {
    /// Name in traces (VCD scope): ASCII letters, digits, `_`, `-`, `.`.
    pub name: String,
    /// The controller.
    pub chip: ChipConfig,
    /// Frequency error of the node's MCLK in ppm (positive: fast).
    pub mclk_error_ppm: f64,
    /// Time one host bus access takes.
    pub bus_access: Duration,
}

impl NodeConfig {
    /// A node named `name` with `chip`, an exact clock and a 100 ns bus access.
    pub fn new(name: &str, chip: ChipConfig) -> Self {
        NodeConfig {
            name: name.to_owned(),
            chip,
            mclk_error_ppm: 0.0,
            bus_access: Duration::from_nanos(100),
        }
    }
}

/// How segments reach the controllers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Delivery {
    /// Every segment goes to every receiver it reaches, and each repeater's output is taken
    /// from its chip, hop by hop (one event per hop): the reference path.
    Exact,
    /// A repeater that only forwards costs no event: arrival times along the ring are sums
    /// of delays; slaves get only what the master sends and what is not a telegram or
    /// filler of another slave (they ignore other slaves' ATs, 410B §1).
    #[default]
    Fast,
}

/// Which capture format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaptureFormat {
    /// Classic pcap.
    Pcap,
    /// pcapng.
    PcapNg,
}

/// Which traces a run writes (all off by default).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TraceConfig {
    /// Telegram log format, if any.
    pub log: Option<LogFormat>,
    /// Only the telegrams on this segment go to the log and the hash (`None`: every segment).
    pub log_segment: Option<SegmentId>,
    /// A capture of the telegrams seen on one segment.
    pub capture: Option<(SegmentId, CaptureFormat)>,
    /// VCD of these pins of these nodes (by index).
    pub vcd: Vec<(usize, PinSet)>,
    /// Keep a hash over the records (of `log_segment`).
    pub hash: bool,
}

impl TraceConfig {
    /// Whether any record-based trace is on.
    pub fn records(&self) -> bool {
        self.log.is_some() || self.capture.is_some() || self.hash
    }
}

/// A whole run.
#[derive(Debug, Clone, PartialEq)]
pub struct SimConfig {
    /// Fibre ring or RS-485 bus.
    pub topology: Topology,
    /// Node 0 is the master, then slave 1, 2, … in ring order.
    pub nodes: Vec<NodeConfig>,
    /// Faults, scheduled in simulated time.
    pub faults: Vec<Fault>,
    /// Seed of every random choice (bit errors).
    pub seed: u64,
    /// Reference or fast delivery.
    pub delivery: Delivery,
    /// Traces to write.
    pub traces: TraceConfig,
}

/// Most slaves on one ring (sercos-telegrams: addresses 1–254).
pub const MAX_SLAVES: usize = 254;
