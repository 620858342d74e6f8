//! `sercon ring`: runs a full-stack simulated ring (the library's [`sercon_cli::ring`]) and
//! prints its report; a progress bar on stderr when it is a terminal.

use crate::stdout_lines::say;
use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use sercon_cli::ring::{self, FaultSpec, NodeRef, RingSpec, RunResult, parse_duration};
use sercon_model::pins::Pin;

use crate::ring_shape::RingShape;

/// Arguments of `sercon ring`.
#[derive(Debug, Args)]
pub struct RingArgs {
    #[command(flatten)]
    shape: RingShape,
    /// Seconds of phase-4 operation (e.g. 3, 0.5, or 1500ms).
    #[arg(long, value_parser = parse_seconds)]
    seconds: Option<sercos_wire::time::Duration>,
    /// Seed of every random choice (bit errors).
    #[arg(long)]
    seed: Option<u64>,
    /// A fault, repeatable (the forms in the help text below, `ring::fault_spec`).
    #[arg(
        long,
        value_name = "FAULT",
        help = "A fault, repeatable: break:N@T1..T2, ber:RATE[:N][@T1..T2], power:N@T1..T2, \
                burst:N:BITS@T, drift:N:PPM@T, distort:N@T1..T2 (N a drive address or \
                \"master\"; times from the first arrival in phase 4)"
    )]
    fault: Vec<FaultSpec>,
    /// Telegram log of every fibre (text; JSON lines if the name ends in .jsonl).
    #[arg(long, value_name = "FILE")]
    log: Option<PathBuf>,
    /// Only this fibre in the log (fibre k runs from node k to node k + 1; 0 = master out).
    #[arg(long, value_name = "K")]
    log_segment: Option<usize>,
    /// Print the report as one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// VCD waveform of the chips' pins: INT0, INT1, CON_CLK and TxD of every node unless
    /// --vcd-pins / --vcd-nodes choose.
    #[arg(long, value_name = "FILE")]
    vcd: Option<PathBuf>,
    /// The pins in the VCD, comma-separated datasheet names (INT0, INT1, CON_CLK, DIV_CLK,
    /// WDOGN, IDLE, REACTN, L_ERRN, DMAREQR, DMAREQT, TxD; case and `_` do not matter). A
    /// drive's REACTN runs the ring on the simulator's slower reference path, the one that
    /// hands every receiver all it hears.
    #[arg(long, value_name = "PINS", value_delimiter = ',', value_parser = ring::pin_named)]
    vcd_pins: Option<Vec<Pin>>,
    /// The nodes in the VCD, comma-separated: `master` and drive addresses (e.g.
    /// master,1,3).
    #[arg(long, value_name = "NODES", value_delimiter = ',')]
    vcd_nodes: Option<Vec<NodeRef>>,
    /// pcap of one fibre (default: the one into the master, which carries every telegram)
    /// for Wireshark with contrib/wireshark/sercos2.lua.
    #[arg(long, value_name = "FILE")]
    pcap: Option<PathBuf>,
    /// The fibre of the pcap.
    #[arg(long, value_name = "K")]
    pcap_segment: Option<usize>,
    /// The master's service channel as JSON lines (the schema of `sercon capture transcript
    /// --json`).
    #[arg(long, value_name = "FILE")]
    transcript: Option<PathBuf>,
    /// Run on the simulator's reference path (every repeater's output taken from its chip,
    /// no slave run ahead): the same run as without, more slowly; a check of the fast path
    /// on this ring. Without it, a run whose telegrams meet at a repeater where the fast
    /// path cannot follow the chips is run again on the reference path by itself.
    #[arg(long)]
    reference: bool,
}

fn parse_seconds(text: &str) -> Result<sercos_wire::time::Duration, String> {
    let with_unit = if text.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
        format!("{text}s")
    } else {
        text.to_string()
    };
    parse_duration(&with_unit)
        .ok_or_else(|| format!("{text:?} is not a time such as 3, 0.5 or 1500ms"))
}

/// The spec from the config file (if any) with the options applied over it.
pub(crate) fn spec_of(args: &RingArgs) -> Result<RingSpec> {
    let mut spec = args.shape.spec()?;
    if let Some(s) = args.seconds {
        spec.run_for = s;
    }
    if let Some(s) = args.seed {
        spec.seed = s;
    }
    spec.faults.extend(args.fault.iter().cloned());
    spec.reference |= args.reference;
    let t = &mut spec.traces;
    for (slot, arg) in [
        (&mut t.log, &args.log),
        (&mut t.vcd, &args.vcd),
        (&mut t.pcap, &args.pcap),
        (&mut t.transcript, &args.transcript),
    ] {
        if arg.is_some() {
            slot.clone_from(arg);
        }
    }
    if args.vcd_pins.is_some() {
        t.vcd_pins.clone_from(&args.vcd_pins);
    }
    if args.vcd_nodes.is_some() {
        t.vcd_nodes.clone_from(&args.vcd_nodes);
    }
    if args.log_segment.is_some() {
        t.log_segment = args.log_segment;
    }
    if args.pcap_segment.is_some() {
        t.pcap_segment = args.pcap_segment;
    }
    Ok(spec)
}

/// Runs `sercon ring`.
pub fn run(args: RingArgs) -> Result<()> {
    let spec = spec_of(&args)?;
    // The master plans the cycle in phase 2 from what the drives report; the emulated
    // drives' parameters are known here, so a cycle too short is said at once.
    sercon_cli::full_stack::plan_ring(&spec)?;
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = ProgressBar::new(spec.run_for.as_micros().max(1));
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} [{bar:30}] {percent:>3}%")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar
    });
    let started = std::time::Instant::now();
    let outcome = ring::run(&spec, &mut |p| {
        if let Some(bar) = &bar {
            bar.set_position(p.operating.as_micros());
            bar.set_message(format!(
                "t = {:.3} s, phase {}{}",
                p.now.as_secs_f64(),
                p.phase,
                // A fast run whose telegrams met at a repeater is run again (`ring::run`).
                if p.reference && !spec.reference {
                    ", again on the reference path (telegrams met at a repeater)"
                } else {
                    ""
                }
            ));
        }
    })?;
    let wall = started.elapsed();
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    ring::write_traces(&spec.traces, &outcome).context("traces")?;
    let report = &outcome.report;
    // A closed stdout (`sercon ring | head`) ends the output quietly; the exit status below
    // still says whether the ring reached phase 4.
    if args.json {
        say!("{}", serde_json::to_string(report)?);
    } else if crate::stdout_lines::write(&report.to_text()) {
        say!("wall time: {:.2} s", wall.as_secs_f64());
    }
    if report.result != RunResult::Phase4 {
        bail!(
            "the ring did not reach phase 4 (master in phase {}, {})",
            report.final_phase,
            report.final_progress
        );
    }
    Ok(())
}
