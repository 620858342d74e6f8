//! `sercon bench`: runs the fixed ring scenarios of `sercos_sim::scenario` and the
//! full-stack scenarios of `sercon_cli::full_stack` (master driver and emulated drives
//! running; JSON lines carry `"stack":"full"`), and prints the real-time factor (simulated
//! seconds per wall second) of each.

use anyhow::{Context, Result, bail};
use clap::Args;
use sercon_cli::full_stack;
use sercos_sim::scenario;
use sercos_wire::time::Duration;

/// Arguments of `sercon bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Print one JSON object per scenario and line.
    #[arg(long)]
    json: bool,
    /// Simulated time per scenario in milliseconds.
    #[arg(long, default_value_t = 200)]
    sim_ms: u64,
    /// Run only the scenario of this name (ring-8, ring-n8, ring-32, ring-128, ring-254;
    /// full stack: stack-8, phaseup-8, stack-n8).
    #[arg(long)]
    scenario: Option<String>,
    /// Which scenarios: the static ring's, the full stack's, or both.
    #[arg(long, value_enum, default_value_t = Stack::All)]
    stack: Stack,
}

/// Which group of scenarios `sercon bench` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Stack {
    /// Static phase-4 rings (`sercos_sim::scenario`): controllers and ring only.
    Ring,
    /// Master driver, emulated drives, controllers and ring (`sercon_cli::full_stack`).
    Full,
    /// Both.
    All,
}

/// Runs the scenarios.
pub fn run(args: BenchArgs) -> Result<()> {
    let wanted = |name: &str| args.scenario.as_deref().is_none_or(|n| n == name);
    let ring: Vec<_> = if args.stack == Stack::Full {
        Vec::new()
    } else {
        scenario::all()
            .into_iter()
            .filter(|s| wanted(&s.name))
            .collect()
    };
    let full: Vec<_> = if args.stack == Stack::Ring {
        Vec::new()
    } else {
        match &args.scenario {
            Some(name) => full_stack::by_name(name).into_iter().collect(),
            None => full_stack::all(),
        }
    };
    if ring.is_empty() && full.is_empty() {
        bail!(
            "no scenario named {:?}",
            args.scenario.clone().unwrap_or_default()
        );
    }
    for s in ring {
        let cycle_us = u64::from(s.ring.cycle_us).max(1);
        let cycles = (args.sim_ms.saturating_mul(1000) / cycle_us).max(1);
        let r = scenario::run(&s, cycles).with_context(|| format!("scenario {}", s.name))?;
        if args.json {
            println!("{}", r.to_json());
        } else {
            println!(
                "{:<9} {:>3} slaves {:>2} Mbit/s {:>5} µs cycle: {:.3} s simulated in {:.3} s, {:.1}× real time, {:.1} µs wall per cycle",
                r.scenario,
                r.slaves,
                r.bit_rate_mbit,
                r.cycle_us,
                r.sim_s,
                r.wall_s,
                r.rtf,
                r.wall_us_per_cycle
            );
        }
    }
    let mut failed = Vec::new();
    for s in full {
        let sim = Duration::from_millis(args.sim_ms);
        let r = match full_stack::run(&s, sim) {
            Ok(r) => r,
            Err(e) => {
                // The other scenarios still run; the exit status says one failed.
                if args.json {
                    let error = serde_json::Value::String(e.to_string());
                    println!(
                        "{{\"scenario\":\"{}\",\"stack\":\"full\",\"slaves\":{},\"error\":{error}}}",
                        s.name, s.drives
                    );
                } else {
                    println!("{:<9} {:>3} drives: failed: {e}", s.name, s.drives);
                }
                failed.push(s.name);
                continue;
            }
        };
        if args.json {
            println!("{}", r.to_json());
        } else {
            let rss = r
                .peak_rss_mib
                .map_or_else(|| "?".to_string(), |m| format!("{m:.1}"));
            println!(
                "{:<9} {:>3} drives {:>2} Mbit/s {:>5} µs cycle, full stack: {:.3} s simulated in {:.3} s, {:.1}× real time, {:.1} µs wall per cycle; phase-up {:.3} s simulated in {:.3} s; peak RSS {} MiB",
                r.scenario,
                r.slaves,
                r.bit_rate_mbit,
                r.cycle_us,
                r.sim_s,
                r.wall_s,
                r.rtf,
                r.wall_us_per_cycle,
                r.phaseup_sim_s,
                r.phaseup_wall_s,
                rss
            );
        }
    }
    if !failed.is_empty() {
        bail!("scenarios failed: {}", failed.join(", "));
    }
    Ok(())
}
