//! `sercon`: the command line of the sercon project.
//!
//! Thin by design (DESIGN.md): it parses arguments, calls the crates, and turns errors into
//! one clear line and a non-zero exit.

use clap::{Parser, Subcommand};

mod bench;
mod capture;
mod idn_cmd;
mod idn_text;
mod ring_cmd;
mod ring_shape;
mod script;
mod stdout_lines;

/// SERCOS interface tools: line captures, the SERCON controller model, simulated rings.
#[derive(Debug, Parser)]
#[command(name = "sercon", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Measure the ring simulator's speed on fixed scenarios (real-time factor).
    Bench(bench::BenchArgs),
    /// Decode real SERCOS II line captures.
    #[command(subcommand)]
    Capture(capture::CaptureCommand),
    /// Read, write, list and describe a drive's IDNs through the service channel of a
    /// simulated ring (as `soe_read` / `soe_write`).
    #[command(subcommand)]
    Idn(idn_cmd::IdnCommand),
    /// Run a simulated ring: a master and emulated drives brought up to phase 4, cyclic
    /// operation with a motion profile, faults, diagnostics and traces.
    Ring(ring_cmd::RingArgs),
    /// Run a scripted register sequence on a controller model and write its pins as VCD.
    Script(script::ScriptArgs),
}

fn main() -> std::process::ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            // --help, --version: print as clap formats them.
            let _ = e.print();
            return std::process::ExitCode::SUCCESS;
        }
        Err(e) => {
            // One clear line: clap's first line (it names the option and the value), without
            // its usage hint.
            let text = e.render().to_string();
            let line = text.lines().next().unwrap_or_default();
            eprintln!("sercon: {}", line.trim_start_matches("error: "));
            return std::process::ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Bench(args) => bench::run(args),
        Command::Capture(cmd) => capture::run(cmd),
        Command::Idn(cmd) => idn_cmd::run(cmd),
        Command::Ring(args) => ring_cmd::run(args),
        Command::Script(args) => script::run(args),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // One clear line: the error and its causes, joined.
            eprintln!("sercon: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
