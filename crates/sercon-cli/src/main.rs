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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The words of sercon's command lines, and values near them: subcommands, options, good
    /// and bad values.
    const WORDS: &[&str] = &[
        "ring",
        "bench",
        "capture",
        "decode",
        "transcript",
        "idn",
        "read",
        "write",
        "list",
        "describe",
        "script",
        "--drives",
        "--baud",
        "--cycle-us",
        "--seconds",
        "--seed",
        "--fault",
        "--vcd",
        "--vcd-pins",
        "--vcd-nodes",
        "--log",
        "--log-segment",
        "--pcap",
        "--pcap-segment",
        "--transcript",
        "--json",
        "--reference",
        "--variant",
        "--telegram-type",
        "--config",
        "--sim-ms",
        "--scenario",
        "--stack",
        "--repeat",
        "--force",
        "--coding",
        "break:1@1s..2s",
        "ber:1e-5",
        "ber:2:3@1s..",
        "drift:2:100@0ms",
        "power:master@1s..2s",
        "power:1@2s..1s",
        "burst:1:8@1s",
        "distort:1@0s..1s",
        "816",
        "410b",
        "0",
        "1",
        "2",
        "4",
        "8",
        "16",
        "62",
        "254",
        "255",
        "65001",
        "-1",
        "18446744073709551616",
        "1e-5",
        "1.5",
        "0.000001",
        "1500ms",
        "0s",
        "master",
        "master,2",
        "int0,txd",
        "REACTN",
        ",",
        "x",
        "",
        "S-0-0001",
        "P-0-0100",
        "ring-8",
        "stack-n300",
    ];

    /// The other commands, which the test only parses (they would run).
    const OTHER_COMMANDS: &[&[&str]] = &[
        &["bench"],
        &["capture", "decode"],
        &["capture", "transcript"],
        &["idn", "read"],
        &["idn", "write"],
        &["script"],
        &[],
    ];

    fn arg() -> impl Strategy<Value = String> {
        prop_oneof![
            4 => proptest::sample::select(WORDS).prop_map(String::from),
            1 => ".{0,12}",
        ]
    }

    proptest! {
        // No panic from a command line: any words are parsed or refused by clap, and a ring
        // command's spec is built, planned and its simulation set up (all that `sercon ring`
        // does before it runs) or refused.
        #[test]
        fn any_command_line_is_taken_or_refused(
            command in prop_oneof![
                3 => Just(vec!["ring"]),
                1 => proptest::sample::select(OTHER_COMMANDS).prop_map(|c| c.to_vec()),
            ],
            args in proptest::collection::vec(arg(), 0..8),
        ) {
            let argv = ["sercon"]
                .iter()
                .chain(&command)
                .map(|w| w.to_string())
                .chain(args);
            if let Ok(Cli { command: Command::Ring(ring) }) = Cli::try_parse_from(argv)
                && let Ok(spec) = ring_cmd::spec_of(&ring)
                && spec.drives.iter().all(|d| d.idn_file.is_none())
                && sercon_cli::full_stack::plan_ring(&spec).is_ok()
            {
                let _ = sercon_cli::ring::build(&spec, Vec::new(), false);
            }
        }
    }
}
