//! The RS-485 bus of 410B §1 Fig. 4: every node hears every transmitter after the bus delay;
//! overlapping transmissions are garbled and reported (`SimStats::collisions`, the telegram
//! log, 410B §4.2.1 RERR/NERR at the receivers); transmissions that only touch are received
//! intact; `Delivery::Fast` and `Delivery::Exact` agree; any slave count runs.

mod ring_support;

use ring_support::*;
use sercon_regs::{Register, SerconBus};
use sercos_sim::sim::Simulation;
use sercos_sim::static_ring::{RingPlan, StaticRing, at_pattern, mdt_pattern};
use sercos_sim::{Delivery, Topology};
use sercos_wire::time::Duration;

/// Five cycles of 250 µs (the first starts at 0).
const RUN_US: u64 = 1240;
const CYCLES: u16 = 5;

fn bus_ring(slaves: usize) -> StaticRing {
    let mut ring = StaticRing::new(slaves, 250);
    ring.repon = false;
    ring
}

/// Runs `ring` on a bus of `delay`, slave `i`'s MCLK off by `ppm[i - 1]` (moves its AT by
/// about TRT × error, the fine adjustment of the overlaps below).
fn run_bus(
    ring: &StaticRing,
    delay: Duration,
    ppm: &[f64],
    until_us: u64,
) -> (Simulation, Vec<Line>, RingPlan, Vec<u8>) {
    let (mut cfg, hosts, plan) = build(ring);
    cfg.topology = Topology::Bus { delay };
    for (i, p) in ppm.iter().enumerate() {
        cfg.nodes[i + 1].mclk_error_ppm = *p;
    }
    let (sim, out) = run(cfg, hosts, us(until_us));
    (sim, parse_log(&out.log), plan, out.log)
}

/// AT starts of slave `s` on the bus (ps).
fn at_starts(log: &[Line], s: u8) -> Vec<u64> {
    log.iter()
        .filter(|l| !l.master && l.kind == "AT" && l.adr == Some(s))
        .map(|l| l.ps)
        .collect()
}

#[test]
fn every_node_hears_every_other_node_at_the_bus_delay() {
    for delivery in [Delivery::Fast, Delivery::Exact] {
        let mut ring = bus_ring(3);
        ring.delivery = delivery;
        let mut starts = Vec::new();
        for delay_ns in [50u64, 300] {
            let (mut sim, log, plan, _) =
                run_bus(&ring, Duration::from_nanos(delay_ns), &[], RUN_US);
            assert_eq!(sim.stats().collisions, 0);
            assert!(log.iter().all(|l| l.ok && l.seg == 0), "{delivery:?}");
            // Every slave got the master's MDT (its own record, 410B §4.2.1 VAL, no NERR).
            for s in 1..=3 {
                let c = sim.chip_mut(s).expect("slave");
                let h = rx_header(c, plan.slave_mdt_header);
                assert!(h.val && !h.rerr && h.nerr == 0, "slave {s}: {h:?}");
                assert_eq!(c.read_ram(plan.slave_mdt_data), mdt_pattern(s, 0));
                // Its own AT data is what it sends: its own telegram did not land in it.
                assert_eq!(c.read_ram(plan.slave_at_data), at_pattern(s, 0));
            }
            // The master got every slave's AT.
            for s in 1..=3 {
                let c = sim.chip_mut(0).expect("master");
                let h = rx_header(c, plan.master_at_header[s - 1]);
                assert!(h.val && !h.rerr && h.nerr == 0, "AT {s}: {h:?}");
                let at = plan.master_at_data[s - 1].expect("stored");
                assert_eq!(c.read_ram(at), at_pattern(s, 0), "AT {s}");
            }
            let mst: Vec<u64> = log
                .iter()
                .filter(|l| l.kind == "MST")
                .map(|l| l.ps)
                .collect();
            starts.push((mst, (1..=3).map(|s| at_starts(&log, s)).collect::<Vec<_>>()));
        }
        // The master's MST goes out at the same time; every slave hears it one bus delay
        // later and answers TRT after it, so each AT on the bus moves by the change of delay
        // (kept within the master's TRT check, TCHK: a round trip of microseconds is RERR;
        // 250 ns, four bit times, keeps the phase to the receivers' clock edges).
        let ((mst_a, ats_a), (mst_b, ats_b)) = (&starts[0], &starts[1]);
        assert_eq!(mst_a, mst_b);
        for (a, b) in ats_a.iter().zip(ats_b) {
            assert_eq!(a.len(), usize::from(CYCLES));
            for (x, y) in a.iter().zip(b) {
                assert_eq!(y - x, 250_000, "{delivery:?}");
            }
        }
    }
}

/// Slave 2's AT `d_us` µs (+ `ppm` of its MCLK) after slave 1's planned one.
fn overlap_run(
    d_us: u16,
    ppm: f64,
    delivery: Delivery,
) -> (Simulation, Vec<Line>, RingPlan, Vec<u8>) {
    let t = bus_ring(2).build().expect("fits").2.at_trt_us[0];
    let mut ring = bus_ring(2);
    ring.delivery = delivery;
    ring.at_trt_override = Some(vec![t + 40, t + 40 + d_us]);
    run_bus(&ring, Duration::from_nanos(50), &[0.0, ppm], RUN_US)
}

/// Bit time at 16 Mbit/s (ps).
const BIT_PS: u64 = 62_500;

/// Slave 2's AT `d_us` after slave 1's planned one, its MCLK off by `ppm`.
struct Case {
    d_us: u16,
    ppm: f64,
}

/// Runs the case and checks what the later telegram and the counters show; returns, per
/// cycle, slave 2's AT start after slave 1's (ps) and whether it collided.
fn check_case(c: &Case, overlap: bool) -> Vec<(i64, bool)> {
    let (mut sim, log, plan, _) = overlap_run(c.d_us, c.ppm, Delivery::Fast);
    let name = format!("d {} µs, {} ppm", c.d_us, c.ppm);
    // Slave 1's AT starts every cycle; slave 2's is in the log as AT 2 or, garbled, as a
    // line error (no address).
    let a = at_starts(&log, 1);
    assert_eq!(a.len(), usize::from(CYCLES), "{name}");
    let cycle = 250_000_000u64;
    let mut per_cycle = Vec::new();
    for (k, s1) in a.iter().enumerate() {
        let later: Vec<&Line> = log
            .iter()
            .filter(|l| !l.master && l.ps / cycle == k as u64 && l.adr != Some(1))
            .collect();
        assert_eq!(later.len(), 1, "{name}: cycle {k}");
        let d = i64::try_from(later[0].ps).expect("fits") - i64::try_from(*s1).expect("fits");
        per_cycle.push((d, !later[0].ok));
    }
    let garbled = per_cycle.iter().filter(|p| p.1).count();
    // Reported: one collision per garbled telegram, a line error in the log for each.
    assert_eq!(sim.stats().collisions, garbled as u64, "{name}");
    assert_eq!(log.iter().filter(|l| !l.ok).count(), garbled, "{name}");
    let m = sim.chip_mut(0).expect("master");
    let h2 = rx_header(m, plan.master_at_header[1]);
    let h1 = rx_header(m, plan.master_at_header[0]);
    // The later telegram (slave 2's) never reaches the master's buffer when garbled: NERR
    // counts it, once per cycle (410B §4.2.1).
    assert_eq!(usize::from(h2.nerr), garbled, "{name}: {h2:?}");
    if overlap {
        assert!(garbled > 0, "{name}");
    } else {
        assert_eq!(garbled, 0, "{name}");
        assert!(!h1.rerr && h1.nerr == 0 && h1.val, "{name}: AT 1 {h1:?}");
        assert!(!h2.rerr && h2.val, "{name}: AT 2 {h2:?}");
    }
    for s in 1..=2 {
        let at = plan.master_at_data[s - 1].expect("stored");
        let v = m.read_ram(at);
        if s == 2 && garbled == usize::from(CYCLES) {
            assert!(h2.rerr, "{name}");
            assert_eq!(v, 0, "{name}: AT 2 data");
        } else if garbled == 0 {
            assert_eq!(v, at_pattern(s, 0), "{name}: AT {s} data");
        }
    }
    per_cycle
}

/// Finds, by bisection on slave 2's clock error at `d_us`, the last colliding and the first
/// clean case around the end of slave 1's AT.
fn boundary(d_us: u16) -> (Case, Case) {
    // A negative error makes slave 2's clock slow: its AT comes later.
    let (mut lo, mut hi) = (0.0f64, -20_000.0f64);
    let collides = |p: f64| overlap_run(d_us, p, Delivery::Fast).0.stats().collisions > 0;
    assert!(collides(lo) && !collides(hi), "bracket at {d_us} µs");
    for _ in 0..40 {
        let mid = (lo + hi) / 2.0;
        if collides(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (Case { d_us, ppm: lo }, Case { d_us, ppm: hi })
}

#[test]
fn overlapping_transmissions_are_garbled_and_reported_touching_ones_are_not() {
    // Whole (same start), at the start, in the middle, near the end of slave 1's AT.
    for d in [0u16, 1, 3, 6, 9, 10] {
        check_case(&Case { d_us: d, ppm: 0.0 }, true);
    }
    // The end of slave 1's AT lies between 10 and 14 µs after its start.
    let d = (9..14)
        .find(|&d| overlap_run(d + 1, 0.0, Delivery::Fast).0.stats().collisions == 0)
        .expect("a clean offset");
    let (last, first) = boundary(d);
    let mut seen = check_case(&last, true);
    seen.extend(check_case(&first, false));
    // Per cycle (the chips start on their own clock edges, so the offset varies a little):
    // every garbled telegram started before every clean one, and the last garbled start
    // and the first clean one are less than a bit apart (the end of slave 1's AT: an overlap
    // of less than one bit is garbled, a telegram touching the end is not).
    let max_garbled = seen
        .iter()
        .filter(|p| p.1)
        .map(|p| p.0)
        .max()
        .expect("garbled");
    let min_clean = seen
        .iter()
        .filter(|p| !p.1)
        .map(|p| p.0)
        .min()
        .expect("clean");
    assert!(
        max_garbled < min_clean && min_clean - max_garbled < i64::try_from(BIT_PS).expect("fits"),
        "{max_garbled} {min_clean}"
    );
    // Well apart.
    check_case(&Case { d_us: 20, ppm: 0.0 }, false);
}

/// Every node's RAM and status registers.
fn chips(sim: &mut Simulation) -> Vec<Vec<u16>> {
    (0..sim.node_count())
        .map(|i| {
            let c = sim.chip_mut(i).expect("node");
            let mut v: Vec<u16> = (0..2048).map(|a| c.read_ram(a)).collect();
            for r in [Register::Ctrl2, Register::IntFlagsLo, Register::IntFlagsHi] {
                v.push(c.read_register(r.address()));
            }
            v
        })
        .collect()
}

#[test]
fn fast_and_exact_agree_on_a_bus() {
    for (d, ppm) in [(30u16, 0.0), (0, 0.0), (5, 0.0), (11, -3000.0), (12, 0.0)] {
        let (mut f, _, _, flog) = overlap_run(d, ppm, Delivery::Fast);
        let (mut e, _, _, elog) = overlap_run(d, ppm, Delivery::Exact);
        assert_eq!(
            String::from_utf8_lossy(&flog),
            String::from_utf8_lossy(&elog),
            "d {d}"
        );
        let (sf, se) = (f.stats(), e.stats());
        assert_eq!(sf.collisions, se.collisions, "d {d}");
        assert_eq!(sf.late, se.late, "d {d}");
        assert_eq!(sf.out_of_order, se.out_of_order, "d {d}");
        assert_eq!(chips(&mut f), chips(&mut e), "d {d}");
    }
}

#[test]
fn any_slave_count_runs_on_a_bus() {
    for slaves in [1usize, 2, 3, 17, 100, 254] {
        for collide in [false, true] {
            let mut ring = StaticRing::new(slaves, 250);
            ring.repon = false;
            let Ok((_, _, plan)) = ring.build() else {
                // A cycle too short for the slaves: a longer one.
                ring.cycle_us = 65_000;
                let (_, _, plan) = ring.build().expect("fits");
                check_bus(&mut ring, &plan, collide, slaves);
                continue;
            };
            check_bus(&mut ring, &plan, collide, slaves);
        }
    }
}

fn check_bus(ring: &mut StaticRing, plan: &RingPlan, collide: bool, slaves: usize) {
    if collide {
        ring.at_trt_override = Some(vec![plan.at_trt_us[0]; slaves]);
    }
    let until = 2 * u64::from(ring.cycle_us) + 10;
    let (sim, log, _, _) = run_bus(ring, Duration::from_nanos(50), &[], until);
    let st = sim.stats();
    if collide && slaves > 1 {
        assert!(st.collisions > 0, "{slaves}");
    } else {
        assert_eq!(st.collisions, 0, "{slaves}");
        assert!(log.iter().all(|l| l.ok), "{slaves}");
    }
}
