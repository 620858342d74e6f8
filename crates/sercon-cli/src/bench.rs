//! `sercon bench`: runs the fixed ring scenarios of `sercos_sim::scenario` and prints the
//! real-time factor (simulated seconds per wall second) of each.

use anyhow::{Context, Result, bail};
use clap::Args;
use sercos_sim::scenario;

/// Arguments of `sercon bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Print one JSON object per scenario and line.
    #[arg(long)]
    json: bool,
    /// Simulated time per scenario in milliseconds.
    #[arg(long, default_value_t = 200)]
    sim_ms: u64,
    /// Run only the scenario of this name (ring-8, ring-n8, ring-32, ring-128, ring-254).
    #[arg(long)]
    scenario: Option<String>,
}

/// Runs the scenarios.
pub fn run(args: BenchArgs) -> Result<()> {
    let all = scenario::all();
    let chosen: Vec<_> = match &args.scenario {
        Some(name) => all.into_iter().filter(|s| &s.name == name).collect(),
        None => all,
    };
    if chosen.is_empty() {
        bail!("no scenario named {:?}", args.scenario.unwrap_or_default());
    }
    for s in chosen {
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
    Ok(())
}
