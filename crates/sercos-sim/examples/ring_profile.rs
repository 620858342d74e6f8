//! Runs one `sercon bench` scenario for a number of cycles (for profilers such as
//! `valgrind --tool=callgrind`): `ring_profile <scenario> <cycles> [events|observable]`.
//! `ring-8x<k>` is `ring-8` with `k` slaves (1 to 254): the cost per cycle at a few `k`
//! splits into a fixed part and a part per slave (docs/performance.md, session 10). A name
//! ending in `-at-first` lays the scenario's telegrams out with the MDT after the ATs
//! (`StaticRing::mdt_after_ats`).

use sercos_sim::scenario;
use sercos_sim::sim::Lookahead;
use sercos_wire::time::Duration;

fn main() {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "ring-8".into());
    let (base, at_first) = match name.strip_suffix("-at-first") {
        Some(b) => (b.to_string(), true),
        None => (name.clone(), false),
    };
    let cycles: u64 = args.next().and_then(|c| c.parse().ok()).unwrap_or(100);
    let lookahead = match args.next().as_deref() {
        Some("observable") => Lookahead::Observable,
        _ => Lookahead::Events,
    };
    let resized = base
        .strip_prefix("ring-8x")
        .and_then(|k| k.parse::<usize>().ok())
        .filter(|k| (1..=254).contains(k))
        .map(|k| {
            let mut s = scenario::ring_8();
            s.ring.slaves = k;
            s
        });
    let Some(mut s) = resized.or_else(|| scenario::all().into_iter().find(|s| s.name == base))
    else {
        eprintln!("no scenario {name}");
        std::process::exit(2);
    };
    s.ring.mdt_after_ats = at_first;
    let mut sim = match scenario::prepare(&s) {
        Ok(sim) => sim,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    sim.set_lookahead(lookahead);
    let cycle = Duration::from_micros(u64::from(s.ring.cycle_us));
    let before = sim.stats();
    let wall = std::time::Instant::now();
    let end = sim.now() + cycle.saturating_mul(cycles);
    if let Err(e) = sim.run_until(end) {
        eprintln!("{e}");
        std::process::exit(1);
    }
    let wall_s = wall.elapsed().as_secs_f64();
    let sim_s = cycle.as_secs_f64() * cycles as f64;
    let after = sim.stats();
    println!(
        "{name} {lookahead:?}: {:.1} us/cycle, {:.1}x real time, {:.1} events/cycle, {:.1} deliveries/cycle, {:.1} run-aheads/cycle, {} late",
        wall_s * 1e6 / cycles as f64,
        sim_s / wall_s,
        (after.events - before.events) as f64 / cycles as f64,
        (after.deliveries - before.deliveries) as f64 / cycles as f64,
        (after.run_aheads - before.run_aheads) as f64 / cycles as f64,
        after.late - before.late
    );
}
