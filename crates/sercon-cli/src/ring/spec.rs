//! What a ring run is made of: the chips, the line, the cycle, the drives with their IDN
//! files and fibres, the faults and the traces.

use std::path::PathBuf;

use sercon_model::pins::Pin;
use sercon_regs::Variant;
use sercos_wire::time::{BitRate, Duration};

use super::fault_spec::{FaultSpec, NodeRef};

/// One emulated drive on the ring, in ring order (the first one after the master first).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DriveSpec {
    /// Its SERCOS address (1–254, sercos-telegrams.md).
    pub address: u8,
    /// Its IDN database as a TOML file (`sercos_drive::config_file`); `None`: the standard
    /// catalogue.
    pub idn_file: Option<PathBuf>,
    /// Length of the fibre from the node before it (the master for the first drive) to its
    /// receiver, metres.
    pub fibre_m: u32,
}

/// Which traces to write, and where.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TraceSpec {
    /// Telegram log of every segment (text; JSON lines if the name ends in `.jsonl` or
    /// `.json`).
    pub log: Option<PathBuf>,
    /// Only this segment (fibre index) in the log.
    pub log_segment: Option<usize>,
    /// VCD of the chips' pins (by default INT0, INT1, CON_CLK, TxD of every node).
    pub vcd: Option<PathBuf>,
    /// The pins in the VCD (`None`: INT0, INT1, CON_CLK and TxD).
    pub vcd_pins: Option<Vec<Pin>>,
    /// The nodes in the VCD (`None`: every node).
    pub vcd_nodes: Option<Vec<NodeRef>>,
    /// pcap of one segment (the fibre into the master, which carries every telegram, unless
    /// `pcap_segment` says otherwise).
    pub pcap: Option<PathBuf>,
    /// The segment of the pcap.
    pub pcap_segment: Option<usize>,
    /// The master's service channel as JSON lines (`sercon capture transcript --json`).
    pub transcript: Option<PathBuf>,
}

/// A whole ring run.
#[derive(Debug, Clone, PartialEq)]
pub struct RingSpec {
    /// The controller of every node.
    pub variant: Variant,
    /// The line's bit rate.
    pub bit_rate: BitRate,
    /// Communication cycle time tScyc (S-0-0002), µs.
    pub cycle_us: u32,
    /// Simulated time of phase-4 operation, counted from the first time the master reaches
    /// phase 4.
    pub run_for: Duration,
    /// Simulated time the master has to reach phase 4 the first time.
    pub phase_up_limit: Duration,
    /// Seed of every random choice (bit errors).
    pub seed: u64,
    /// The drives in ring order.
    pub drives: Vec<DriveSpec>,
    /// Length of the fibre from the last drive back to the master, metres.
    pub return_fibre_m: u32,
    /// Faults; their times count from the first time the master reaches phase 4.
    pub faults: Vec<FaultSpec>,
    /// The motion profile the master commands in phase 4.
    pub profile: super::motion_profile::MotionProfile,
    /// Traces.
    pub traces: TraceSpec,
    /// S-0-0015, the telegram type the master writes to every drive: 7 (configured, the
    /// master's lists) or a standard type 0-6 (`sercdrv::master::standard_telegram`).
    pub telegram_type: u16,
    /// Run on the simulator's reference path (`sercos_sim::Delivery::Exact`: every
    /// repeater's output taken from its chip, no slave run ahead) instead of its fast path;
    /// both give the same run, the reference one more slowly (a check of the fast path on
    /// a ring of one's own). A fast run whose telegrams meet at a repeater where the fast
    /// path cannot follow the chips is run again on the reference path ([`super::run`]).
    pub reference: bool,
}

/// Default fibre length between two nodes, metres.
pub const DEFAULT_FIBRE_M: u32 = 10;

impl RingSpec {
    /// `n` drives at addresses 1…n with the standard catalogue and 10 m fibres.
    pub fn with_drives(n: u8) -> Vec<DriveSpec> {
        (1..=n)
            .map(|address| DriveSpec {
                address,
                idn_file: None,
                fibre_m: DEFAULT_FIBRE_M,
            })
            .collect()
    }

    /// Ring position (node index: 0 is the master, drives from 1) of the drive at `address`.
    pub fn position_of(&self, address: u8) -> Option<usize> {
        self.drives
            .iter()
            .position(|d| d.address == address)
            .map(|i| i + 1)
    }
}

impl Default for RingSpec {
    /// The README's first run: a master and 4 drives, SERCON816, 16 Mbit/s, 1 ms cycle, 3 s
    /// of phase-4 operation, seed 1.
    fn default() -> RingSpec {
        RingSpec {
            variant: Variant::Sercon816,
            bit_rate: BitRate::Mbit16,
            cycle_us: 1000,
            run_for: Duration::from_secs(3),
            phase_up_limit: Duration::from_secs(20),
            seed: 1,
            drives: RingSpec::with_drives(4),
            return_fibre_m: DEFAULT_FIBRE_M,
            faults: Vec::new(),
            profile: super::motion_profile::MotionProfile::default(),
            traces: TraceSpec::default(),
            telegram_type: sercdrv::master::TELEGRAM_TYPE_CONFIGURED,
            reference: false,
        }
    }
}
