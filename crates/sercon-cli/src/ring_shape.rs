//! The options that describe a simulated ring, shared by `sercon ring` and `sercon idn`:
//! a config file and the overrides of its drives, controller, bit rate and cycle time.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};
use sercon_cli::ring::{self, RingSpec};
use sercon_regs::Variant;
use sercos_wire::time::BitRate;

/// The controller variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum VariantArg {
    /// SERCON816.
    #[value(name = "816")]
    S816,
    /// SERCON410B (2 and 4 Mbit/s).
    #[value(name = "410b")]
    S410b,
}

/// The shape of the ring: a config file and the options that override it.
#[derive(Debug, Args)]
pub struct RingShape {
    /// A full description of the ring (drives, IDN files, fibre lengths, faults, traces);
    /// the options below override it.
    #[arg(long, value_name = "ring.toml")]
    pub config: Option<PathBuf>,
    /// Number of emulated drives (addresses 1…N, up to 254: sercos-telegrams.md; a ring that
    /// does not fit the master's RAM is refused with the layout's reason).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=254))]
    pub drives: Option<u8>,
    /// Controller of every node.
    #[arg(long, value_enum)]
    pub variant: Option<VariantArg>,
    /// Bit rate in Mbit/s: 2, 4, 8 or 16 (8 and 16 on the SERCON816 only).
    #[arg(long, value_parser = parse_baud)]
    pub baud: Option<BitRate>,
    /// Communication cycle time tScyc in µs (S-0-0002).
    #[arg(long, value_parser = clap::value_parser!(u32).range(62..=65000))]
    pub cycle_us: Option<u32>,
    /// Telegram type S-0-0015 the master writes to every drive: 7 (default) configures the
    /// cyclic data by S-0-0016/S-0-0024 (AT: S-0-0011, S-0-0051, P-0-0019; MDT: S-0-0036);
    /// 0-6 are the standard types (3: MDT S-0-0036 velocity command, AT S-0-0051 position
    /// feedback, the shortest that lets 254 drives run a 4 ms cycle at 16 Mbit/s).
    #[arg(long, value_parser = clap::value_parser!(u16).range(0..=7))]
    pub telegram_type: Option<u16>,
}

impl RingShape {
    /// The ring of the config file (if any, else the defaults) with the options applied.
    pub fn spec(&self) -> Result<RingSpec> {
        let mut spec = match &self.config {
            Some(path) => ring::load_config(path)?,
            None => RingSpec::default(),
        };
        if let Some(n) = self.drives {
            spec.drives = RingSpec::with_drives(n);
        }
        if let Some(v) = self.variant {
            spec.variant = match v {
                VariantArg::S816 => Variant::Sercon816,
                VariantArg::S410b => Variant::Sercon410b,
            };
        }
        if let Some(b) = self.baud {
            spec.bit_rate = b;
        }
        if let Some(c) = self.cycle_us {
            spec.cycle_us = c;
        }
        if let Some(t) = self.telegram_type {
            spec.telegram_type = t;
        }
        if let Some(n) = self.drives {
            // Phase 2 addresses one drive per cycle: a large ring needs longer to phase 4.
            let allowance = sercon_cli::full_stack::phase_up_allowance(n, spec.cycle_us);
            spec.phase_up_limit = spec.phase_up_limit.max(allowance);
        }
        Ok(spec)
    }
}

/// 2, 4, 8 or 16 (Mbit/s; 816 §2.3.1).
fn parse_baud(text: &str) -> Result<BitRate, String> {
    text.parse::<u32>()
        .ok()
        .and_then(BitRate::from_mbit)
        .ok_or_else(|| format!("{text:?} is not 2, 4, 8 or 16 (Mbit/s)"))
}
