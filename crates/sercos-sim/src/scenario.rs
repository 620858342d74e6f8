//! The fixed benchmark scenarios of `sercon bench` and the criterion benches: static
//! phase-4 rings run for a while, measured in simulated seconds per wall second.

use std::time::Instant as WallInstant;

use sercos_wire::time::{Duration, Instant};

use crate::error::SimError;
use crate::sim::Simulation;
use crate::static_ring::StaticRing;

/// One scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// Name (`ring-8`, …).
    pub name: String,
    /// The ring.
    pub ring: StaticRing,
}

/// The result of running a scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchResult {
    /// Scenario name.
    pub scenario: String,
    /// Slaves.
    pub slaves: usize,
    /// Bit rate in Mbit/s.
    pub bit_rate_mbit: u32,
    /// Cycle in µs.
    pub cycle_us: u16,
    /// Communication phase.
    pub phase: u8,
    /// Simulated seconds.
    pub sim_s: f64,
    /// Wall seconds.
    pub wall_s: f64,
    /// Real-time factor: simulated seconds per wall second.
    pub rtf: f64,
    /// Wall microseconds per simulated cycle.
    pub wall_us_per_cycle: f64,
    /// Telegram bytes per cycle (MST, MDT, ATs).
    pub bytes_per_cycle: u64,
    /// Simulation events per cycle: those taken from the event queue. A master's wake taken
    /// within the wake before it (`sim/join_wake.rs`, plain rings of inert hosts) is none,
    /// so ring-8 and ring-254 run at 0.0 ([`crate::SimStats::joined_wakes`] counts those).
    pub events_per_cycle: f64,
    /// Segments handed to receivers per cycle.
    pub deliveries_per_cycle: f64,
    /// Cycles run, unmeasured, to warm the run up before it was measured ([`run`]).
    pub warm_up_cycles: u64,
}

impl BenchResult {
    /// One JSON object on one line.
    pub fn to_json(&self) -> String {
        format!(
            "{{\"scenario\":\"{}\",\"slaves\":{},\"bit_rate_mbit\":{},\"cycle_us\":{},\"phase\":{},\"sim_s\":{:.6},\"wall_s\":{:.6},\"rtf\":{:.3},\"wall_us_per_cycle\":{:.3},\"bytes_per_cycle\":{},\"events_per_cycle\":{:.1},\"deliveries_per_cycle\":{:.1},\"warm_up_cycles\":{}}}",
            self.scenario,
            self.slaves,
            self.bit_rate_mbit,
            self.cycle_us,
            self.phase,
            self.sim_s,
            self.wall_s,
            self.rtf,
            self.wall_us_per_cycle,
            self.bytes_per_cycle,
            self.events_per_cycle,
            self.deliveries_per_cycle,
            self.warm_up_cycles
        )
    }
}

/// `ring-8`: master + 8 slaves, 16 Mbit/s, 250 µs cycle, phase 4, 8 words each way.
pub fn ring_8() -> Scenario {
    Scenario {
        name: "ring-8".into(),
        ring: StaticRing::new(8, 250),
    }
}

/// `ring-n<n>` (`ring-254` for 254): master + n slaves, 16 Mbit/s, 4 ms cycle, 1 word
/// each way.
pub fn ring_n(n: usize) -> Scenario {
    let mut ring = StaticRing::new(n, 4000);
    ring.mdt_words = 1;
    ring.at_words = 1;
    let name = if n == 254 {
        "ring-254".to_string()
    } else {
        format!("ring-n{n}")
    };
    Scenario { name, ring }
}

/// Every scenario `sercon bench` runs: `ring-8` (250 µs, 8 words), and the 4 ms rings of
/// 8, 32, 128 and 254 slaves for the growth of wall time per cycle.
pub fn all() -> Vec<Scenario> {
    vec![ring_8(), ring_n(8), ring_n(32), ring_n(128), ring_n(254)]
}

/// Telegram bytes on the line per cycle (ADR + data + FCS of MST, MDT and every AT).
pub fn bytes_per_cycle(ring: &StaticRing) -> u64 {
    let n = ring.slaves as u64;
    let mst = 2 + 2;
    let mdt = 1 + 2 * n * u64::from(ring.mdt_words) + 2;
    let at = 1 + 2 * u64::from(ring.at_words) + 2;
    mst + mdt + n * at
}

/// Builds the scenario's simulation and runs it for a warm-up cycle.
pub fn prepare(s: &Scenario) -> Result<Simulation, SimError> {
    let (cfg, hosts, _) = s.ring.build()?;
    let mut sim = Simulation::new(cfg, hosts)?;
    let cycle = Duration::from_micros(u64::from(s.ring.cycle_us));
    sim.run_until(Instant::ZERO + cycle)?;
    Ok(sim)
}

/// Runs `s` for `cycles` cycles and measures them, after [`prepare`]'s warm-up cycle and
/// whole cycles more, unmeasured, until `warm_up` of wall time has passed (none for zero).
///
/// A fresh simulation's first cycles run slower than its steady ones (memory touched for the
/// first time, cold caches and branch predictors): on ring-8 a 2 ms measurement straight
/// after the set-up came out 10–15 % low about one time in six, none with 5 ms of warm-up
/// or more (docs/performance.md, "Session 34"). Criterion's benches warm up the same way.
pub fn run(
    s: &Scenario,
    cycles: u64,
    warm_up: std::time::Duration,
) -> Result<BenchResult, SimError> {
    let mut sim = prepare(s)?;
    let cycle = Duration::from_micros(u64::from(s.ring.cycle_us));
    let warm_up_cycles = warm(&mut sim, cycle, warm_up)?;
    let start = sim.now();
    let end = start + cycle.saturating_mul(cycles);
    let before = sim.stats();
    let wall = WallInstant::now();
    sim.run_until(end)?;
    let wall_s = wall.elapsed().as_secs_f64();
    let after = sim.stats();
    let per = |a: u64, b: u64| a.saturating_sub(b) as f64 / cycles.max(1) as f64;
    let sim_s = end.saturating_duration_since(start).as_secs_f64();
    Ok(BenchResult {
        scenario: s.name.clone(),
        slaves: s.ring.slaves,
        bit_rate_mbit: s.ring.bit_rate.mbit(),
        cycle_us: s.ring.cycle_us,
        phase: 4,
        sim_s,
        wall_s,
        rtf: if wall_s > 0.0 {
            sim_s / wall_s
        } else {
            f64::INFINITY
        },
        wall_us_per_cycle: wall_s * 1e6 / cycles.max(1) as f64,
        bytes_per_cycle: bytes_per_cycle(&s.ring),
        events_per_cycle: per(after.events, before.events),
        deliveries_per_cycle: per(after.deliveries, before.deliveries),
        warm_up_cycles,
    })
}

/// Runs `sim` a `cycle` at a time until `warm_up` of wall time has passed; returns the
/// cycles run.
fn warm(
    sim: &mut Simulation,
    cycle: Duration,
    warm_up: std::time::Duration,
) -> Result<u64, SimError> {
    let wall = WallInstant::now();
    let mut cycles = 0u64;
    while wall.elapsed() < warm_up {
        let next = sim.now() + cycle;
        sim.run_until(next)?;
        cycles += 1;
    }
    Ok(cycles)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The warm-up runs whole cycles that are not measured: the measured simulated time
    /// is the cycles asked for, with or without it.
    #[test]
    fn the_warm_up_is_not_measured() {
        let s = ring_n(8);
        let cycle_s = f64::from(s.ring.cycle_us) * 1e-6;
        let Ok(cold) = run(&s, 2, std::time::Duration::ZERO) else {
            panic!("the ring runs");
        };
        assert_eq!(cold.warm_up_cycles, 0);
        let Ok(warm) = run(&s, 2, std::time::Duration::from_millis(1)) else {
            panic!("the ring runs");
        };
        assert!(warm.warm_up_cycles >= 1, "{}", warm.warm_up_cycles);
        for r in [&cold, &warm] {
            assert!((r.sim_s - 2.0 * cycle_s).abs() < 1e-12, "{}", r.sim_s);
        }
        assert!(
            warm.to_json()
                .contains(&format!("\"warm_up_cycles\":{}}}", warm.warm_up_cycles))
        );
    }
}
