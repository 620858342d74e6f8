//! `sercon script`: runs a scripted register sequence on a controller model and writes the
//! traced pins as a VCD waveform. The file format is described in [`format`](mod@format) and in
//! `examples/scripts/README.md`.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::{Args, ValueEnum};
use sercon_model::Chip;
use sercon_model::config::{ChipConfig, Straps};
use sercon_model::pins::{Pin, PinSet};
use sercon_model::vcd_trace::{Timescale, TracedChip, VcdWriter};
use sercon_regs::{SerconBus, Variant};
use sercos_wire::time::Instant;

use sercon_cli::script_format::{self as format, Line, Step};

/// The controller a script runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum VariantArg {
    /// SERCON816.
    #[value(name = "816")]
    Sercon816,
    /// SERCON410B.
    #[value(name = "410b")]
    Sercon410b,
}

/// The timescale of the VCD file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TimescaleArg {
    /// Picoseconds (exact).
    Ps,
    /// Nanoseconds (rounded to the nearest ns).
    Ns,
    /// Microseconds (rounded to the nearest µs).
    Us,
}

/// Arguments of `sercon script`.
#[derive(Debug, Args)]
pub struct ScriptArgs {
    /// The script file (format: examples/scripts/README.md).
    pub file: PathBuf,
    /// The controller to run it on.
    #[arg(long, value_enum, default_value = "816")]
    pub variant: VariantArg,
    /// MCLK frequency in MHz (may have a fraction, e.g. 12.5); default 32 on the 816 and
    /// 20 on the 410B.
    #[arg(long = "mclk-mhz", value_name = "N")]
    pub mclk_mhz: Option<String>,
    /// Write the traced pins as VCD to this file.
    #[arg(long, value_name = "OUT")]
    pub vcd: Option<PathBuf>,
    /// Pins to trace, comma separated (datasheet names).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "CON_CLK,DIV_CLK,INT0,INT1"
    )]
    pub pins: Vec<String>,
    /// Time unit of the VCD file.
    #[arg(long, value_enum, default_value = "ns")]
    pub timescale: TimescaleArg,
}

/// Runs a script.
pub fn run(args: ScriptArgs) -> anyhow::Result<()> {
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    run_to(&args, &mut out)
}

/// Runs a script, printing `read` results to `out`.
pub fn run_to(args: &ScriptArgs, out: &mut dyn Write) -> anyhow::Result<()> {
    let file = args.file.display().to_string();
    let cfg = chip_config(args)?;
    let text = std::fs::read_to_string(&args.file)
        .with_context(|| format!("cannot read script {file}"))?;
    let lines = format::parse(&text, cfg.variant)
        .map_err(|e| anyhow::anyhow!("{file}:{}: {}", e.line, e.what))?;
    let pins = pin_set(&args.pins)?;
    let timescale = match args.timescale {
        TimescaleArg::Ps => Timescale::Picoseconds,
        TimescaleArg::Ns => Timescale::Nanoseconds,
        TimescaleArg::Us => Timescale::Microseconds,
    };

    let mut chip = Chip::new(cfg);
    chip.set_traced_pins(pins);
    let traced = TracedChip::new("chip", pins, |p| chip.pin_level(p))?;
    let mut vcd = match &args.vcd {
        Some(path) => Some(VcdWriter::new(create(path)?, timescale, &[traced])?),
        None => None,
    };
    let mut events = Vec::new();
    for line in &lines {
        execute(&mut chip, line, out)
            .map_err(|what| anyhow::anyhow!("{file}:{}: {what}", line.number))?;
        events.clear();
        chip.drain_pin_events(&mut events);
        if let Some(v) = vcd.as_mut() {
            v.record_all(0, &events)
                .with_context(|| format!("{file}:{}: writing the VCD", line.number))?;
        }
    }
    if let Some(v) = vcd {
        v.finish(chip.now())?;
    }
    Ok(())
}

fn create(path: &Path) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    let f = std::fs::File::create(path)
        .with_context(|| format!("cannot create VCD file {}", path.display()))?;
    Ok(std::io::BufWriter::new(f))
}

fn chip_config(args: &ScriptArgs) -> anyhow::Result<ChipConfig> {
    let mut cfg = match args.variant {
        VariantArg::Sercon816 => ChipConfig::sercon816(),
        VariantArg::Sercon410b => ChipConfig::sercon410b(),
    };
    // Straps: SBAUD = 0; 816 SBAUD16 = 0 (own bit rates), 410B SREGEN = 1 (internal clock
    // regeneration); TM0 = TM1 = 1: no test mode, repeater on after reset (816 §2.3.3).
    cfg.straps = Straps {
        sbaud: false,
        sbaud16: cfg.variant == Variant::Sercon410b,
        tm0: true,
        tm1: true,
    };
    if let Some(mhz) = &args.mclk_mhz {
        cfg.mclk_hz = format::scaled_decimal(mhz, 1_000_000)
            .filter(|hz| *hz > 0)
            .with_context(|| format!("--mclk-mhz {mhz}: not a positive whole number of Hz"))?;
    }
    cfg.validate().context("invalid chip configuration")?;
    Ok(cfg)
}

fn pin_set(names: &[String]) -> anyhow::Result<PinSet> {
    let mut set = PinSet::EMPTY;
    for n in names.iter().map(|n| n.trim()).filter(|n| !n.is_empty()) {
        match Pin::from_name(n) {
            Some(p) => set = set.with(p),
            None => bail!(
                "--pins: unknown pin {n} (known: {})",
                Pin::ALL.map(|p| p.name()).join(", ")
            ),
        }
    }
    Ok(set)
}

/// Executes one line; returns what went wrong as text.
fn execute(chip: &mut Chip, line: &Line, out: &mut dyn Write) -> Result<(), String> {
    let io = |e: std::io::Error| format!("cannot print: {e}");
    match line.step {
        Step::Write { address, value } => chip.write_register(address, value),
        Step::Ram { address, value } => chip.write_ram(address, value),
        Step::Read { address } => {
            let v = chip.read_register(address);
            writeln!(out, "{} {} = 0x{v:04X}", chip.now(), line.text).map_err(io)?;
        }
        Step::ReadRam { address } => {
            let v = chip.read_ram(address);
            writeln!(out, "{} {} = 0x{v:04X}", chip.now(), line.text).map_err(io)?;
        }
        Step::Expect {
            address,
            value,
            mask,
        } => {
            let v = chip.read_register(address);
            if v & mask != value & mask {
                return Err(format!(
                    "`{}` failed at {}: register {address:02X}H reads 0x{v:04X}, expected \
                     0x{value:04X} under mask 0x{mask:04X}",
                    line.text,
                    chip.now()
                ));
            }
        }
        Step::ExpectRam { address, value } => {
            let v = chip.read_ram(address);
            if v != value {
                return Err(format!(
                    "`{}` failed at {}: RAM word 0x{address:04X} reads 0x{v:04X}, expected \
                     0x{value:04X}",
                    line.text,
                    chip.now()
                ));
            }
        }
        Step::Wait(d) => {
            let t = chip
                .now()
                .checked_add(d)
                .ok_or("time beyond the end of representable time")?;
            chip.advance_to(t);
        }
        Step::Until(d) => {
            let t = Instant::ZERO + d;
            if t < chip.now() {
                return Err(format!(
                    "`until` goes back in time: the model is already at {}",
                    chip.now()
                ));
            }
            chip.advance_to(t);
        }
        Step::CycClk(level) => chip.set_cyc_clk(level),
        Step::Rstn(level) => chip.set_rstn(level),
    }
    Ok(())
}
