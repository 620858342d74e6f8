//! `sercon bench`: runs the fixed ring scenarios of `sercos_sim::scenario` and the
//! full-stack scenarios of `sercon_cli::full_stack` (master driver and emulated drives
//! running; JSON lines carry `"stack":"full"`), and prints the real-time factor (simulated
//! seconds per wall second) of each.

use crate::stdout_lines::say;
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
    /// Run only the scenario of this name (static rings: ring-8, ring-n8, ring-n32,
    /// ring-n128, ring-254; full stack: stack-8, phaseup-8, stack-254, stack-nN for N = 1
    /// to 254 drives).
    #[arg(long)]
    scenario: Option<String>,
    /// Which scenarios: the static ring's, the full stack's, or both.
    #[arg(long, value_enum, default_value_t = Stack::All)]
    stack: Stack,
    /// Runs of each scenario, each from a fresh simulation; the fastest is reported, with
    /// the median real-time factor (`"runs"`, `"rtf_median"` in JSON). One run's wall time
    /// on a shared or virtual machine varies by tens of percent.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000))]
    repeat: u32,
    /// Wall milliseconds each static-ring run is warmed up for before it is measured (whole
    /// cycles, not counted; `"warm_up_cycles"` in JSON): a fresh simulation's first cycles
    /// run slower (memory touched for the first time, cold caches). 0: only the one
    /// warm-up cycle.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(0..=60_000))]
    warm_up_ms: u64,
}

/// The fastest of `runs` (by wall time) and the median real-time factor; `None` for no runs.
fn best_of<T>(runs: Vec<T>, wall: impl Fn(&T) -> f64, rtf: impl Fn(&T) -> f64) -> Option<(T, f64)> {
    let mut rtfs: Vec<f64> = runs.iter().map(&rtf).collect();
    rtfs.sort_by(f64::total_cmp);
    let median = match rtfs.len() {
        0 => return None,
        n if n % 2 == 1 => rtfs.get(n / 2).copied().unwrap_or(0.0),
        n => {
            (rtfs.get(n / 2 - 1).copied().unwrap_or(0.0) + rtfs.get(n / 2).copied().unwrap_or(0.0))
                / 2.0
        }
    };
    let best = runs
        .into_iter()
        .min_by(|a, b| wall(a).total_cmp(&wall(b)))?;
    Some((best, median))
}

/// A one-line JSON object with `"build"` ([`BUILD`]) added, and `"runs"` and
/// `"rtf_median"` when there was more than one run.
fn with_build_and_runs(json: String, runs: u32, median: f64) -> String {
    let Some(body) = json.strip_suffix('}') else {
        return json;
    };
    let build = BUILD;
    if runs <= 1 {
        return format!("{body},\"build\":\"{build}\"}}");
    }
    format!("{body},\"build\":\"{build}\",\"runs\":{runs},\"rtf_median\":{median:.3}}}")
}

/// How this `sercon` was built, printed with every figure (`"build"` in JSON): `debug`
/// (debug assertions on: not for measuring), `pgo` (`scripts/pgo-build.sh`, which sets
/// `SERCON_PGO_BUILD`) or `release`.
const BUILD: &str = if cfg!(debug_assertions) {
    "debug"
} else if option_env!("SERCON_PGO_BUILD").is_some() {
    "pgo"
} else {
    "release"
};

/// The text suffix for more than one run.
fn runs_text(runs: u32, median: f64) -> String {
    if runs <= 1 {
        String::new()
    } else {
        format!(", fastest of {runs} runs (median {median:.1}× real time)")
    }
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

/// The message for a `--scenario` that names nothing `--stack` runs: the names there are.
fn unknown_scenario(name: &str, stack: Stack) -> String {
    let ring: Vec<String> = scenario::all().into_iter().map(|s| s.name).collect();
    let full: Vec<String> = full_stack::all().into_iter().map(|s| s.name).collect();
    let in_ring = ring.iter().any(|n| n == name);
    let in_full = full_stack::by_name(name).is_some();
    let other = match stack {
        Stack::Ring if in_full => " (it is a full-stack scenario: --stack full or all)",
        Stack::Full if in_ring => " (it is a static-ring scenario: --stack ring or all)",
        _ => "",
    };
    format!(
        "no scenario named {name:?}{other}; static rings: {}; full stack: {}, stack-n<n> (1 to 254 drives)",
        ring.join(", "),
        full.join(", ")
    )
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
            "{}",
            unknown_scenario(args.scenario.as_deref().unwrap_or_default(), args.stack)
        );
    }
    if !args.json && !say!("{BUILD} build") {
        return Ok(());
    }
    let warm_up = std::time::Duration::from_millis(args.warm_up_ms);
    for s in ring {
        let cycle_us = u64::from(s.ring.cycle_us).max(1);
        let cycles = (args.sim_ms.saturating_mul(1000) / cycle_us).max(1);
        let mut runs = Vec::new();
        for _ in 0..args.repeat {
            runs.push(
                scenario::run(&s, cycles, warm_up)
                    .with_context(|| format!("scenario {}", s.name))?,
            );
        }
        let Some((r, median)) = best_of(runs, |r| r.wall_s, |r| r.rtf) else {
            continue;
        };
        if args.json {
            if !say!("{}", with_build_and_runs(r.to_json(), args.repeat, median)) {
                return Ok(());
            }
        } else {
            if !say!(
                "{:<9} {:>3} slaves {:>2} Mbit/s {:>5} µs cycle: {:.3} s simulated in {:.3} s, {:.1}× real time, {:.1} µs wall per cycle{}",
                r.scenario,
                r.slaves,
                r.bit_rate_mbit,
                r.cycle_us,
                r.sim_s,
                r.wall_s,
                r.rtf,
                r.wall_us_per_cycle,
                runs_text(args.repeat, median)
            ) {
                return Ok(());
            }
        }
    }
    let mut failed = Vec::new();
    for s in full {
        let sim = Duration::from_millis(args.sim_ms);
        let mut runs = Vec::new();
        let mut error = None;
        for _ in 0..args.repeat {
            match full_stack::run(&s, sim) {
                Ok(r) => runs.push(r),
                Err(e) => {
                    error = Some(e);
                    break;
                }
            }
        }
        let best = match error {
            None => best_of(runs, |r| r.wall_s, |r| r.rtf),
            Some(_) => None,
        };
        let (r, median) = match (best, error) {
            (Some(best), _) => best,
            (None, e) => {
                let e = e.map_or_else(|| "no run".to_string(), |e| e.to_string());
                // The other scenarios still run; the exit status says one failed.
                if args.json {
                    let error = serde_json::Value::String(e.clone());
                    if !say!(
                        "{{\"scenario\":\"{}\",\"stack\":\"full\",\"slaves\":{},\"error\":{error}}}",
                        s.name,
                        s.drives
                    ) {
                        return Ok(());
                    }
                } else {
                    if !say!("{:<9} {:>3} drives: failed: {e}", s.name, s.drives) {
                        return Ok(());
                    }
                }
                failed.push(s.name);
                continue;
            }
        };
        if args.json {
            if !say!("{}", with_build_and_runs(r.to_json(), args.repeat, median)) {
                return Ok(());
            }
        } else {
            let rss = r
                .peak_rss_mib
                .map_or_else(|| "?".to_string(), |m| format!("{m:.1}"));
            if !say!(
                "{:<9} {:>3} drives {:>2} Mbit/s {:>5} µs cycle, full stack: {:.3} s simulated in {:.3} s, {:.1}× real time, {:.1} µs wall per cycle; phase-up {:.3} s simulated in {:.3} s; peak RSS {} MiB{}",
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
                rss,
                runs_text(args.repeat, median)
            ) {
                return Ok(());
            }
        }
    }
    if !failed.is_empty() {
        bail!("scenarios failed: {}", failed.join(", "));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn best_of_takes_the_least_wall_time_and_the_median_factor() {
        // (wall, rtf) pairs: the median of 3 is the middle factor, of 4 the mean of the two.
        let three = vec![(2.0, 5.0), (1.0, 10.0), (4.0, 2.5)];
        let (best, median) = best_of(three, |r| r.0, |r| r.1).expect("runs");
        assert_eq!(best, (1.0, 10.0));
        assert_eq!(median, 5.0);
        let four = vec![(2.0, 5.0), (1.0, 10.0), (4.0, 2.5), (2.5, 4.0)];
        let (_, median) = best_of(four, |r| r.0, |r| r.1).expect("runs");
        assert_eq!(median, 4.5);
        assert!(best_of(Vec::<(f64, f64)>::new(), |r| r.0, |r| r.1).is_none());
    }

    #[test]
    fn the_build_is_always_added_to_the_json_and_runs_only_for_more_than_one() {
        let b = BUILD;
        assert_eq!(
            with_build_and_runs("{\"a\":1}".into(), 1, 2.0),
            format!("{{\"a\":1,\"build\":\"{b}\"}}")
        );
        assert_eq!(
            with_build_and_runs("{\"a\":1}".into(), 3, 2.0),
            format!("{{\"a\":1,\"build\":\"{b}\",\"runs\":3,\"rtf_median\":2.000}}")
        );
        // Tests run with debug assertions: such a build says so.
        assert_eq!(cfg!(debug_assertions), b == "debug");
    }
}
