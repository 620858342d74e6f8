//! The RS-485 bus of 410B §1 Fig. 4: every node hears every transmitter after the bus delay;
//! overlapping transmissions are garbled, both of them, and reported (`SimStats::collisions`,
//! the telegram log, 410B §4.2.1 RERR/NERR at the receivers); transmissions that only touch
//! are received intact; `Delivery::Fast` and `Delivery::Exact` agree; any slave count runs.

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

/// Starts of slave `s`'s ATs received intact on the bus (ps).
fn at_starts(log: &[Line], s: u8) -> Vec<u64> {
    log.iter()
        .filter(|l| !l.master && l.ok && l.kind == "AT" && l.adr == Some(s))
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
#[derive(Debug, Clone, Copy)]
struct Case {
    d_us: u16,
    ppm: f64,
}

/// What a case showed: per cycle, which of the two ATs the log has intact and, when both,
/// slave 2's start after slave 1's (ps); and the collisions reported.
struct Outcome {
    cycles: Vec<([bool; 2], Option<i64>)>,
    collisions: u64,
}

impl Outcome {
    /// Cycles in which neither AT was received.
    fn garbled(&self) -> usize {
        self.cycles.iter().filter(|c| c.0 == [false, false]).count()
    }

    /// Whether every cycle has both ATs.
    fn whole(&self) -> bool {
        self.cycles.iter().all(|c| c.0 == [true, true])
    }

    /// Slave 2's start after slave 1's in the cycles that have both.
    fn offsets(&self) -> Vec<i64> {
        self.cycles.iter().filter_map(|c| c.1).collect()
    }
}

/// Per cycle, which slaves' ATs the bus `log` of a run of `slaves` has intact; checks that
/// the master's view is the line's (410B §4.2.1: NERR counts every cycle whose AT the log
/// does not have intact, RERR the last one, the data are those of the last AT received),
/// that a cycle with every AT intact shows nothing else (a garbled one may show frames in
/// error, or nothing where the line held no flag), and that every cycle that loses an AT
/// counts a collision.
fn seen_per_cycle(
    sim: &mut Simulation,
    log: &[Line],
    plan: &RingPlan,
    slaves: u8,
    name: &str,
) -> Vec<Vec<Option<u64>>> {
    let cycle = 250_000_000u64;
    let mut cycles = Vec::new();
    for k in 0..u64::from(CYCLES) {
        let starts: Vec<Option<u64>> = (1..=slaves)
            .map(|s| {
                let v: Vec<u64> = at_starts(log, s)
                    .into_iter()
                    .filter(|t| t / cycle == k)
                    .collect();
                assert!(v.len() <= 1, "{name}: cycle {k}");
                v.first().copied()
            })
            .collect();
        let errors = log
            .iter()
            .filter(|l| !l.master && !l.ok && l.ps / cycle == k)
            .count();
        assert!(
            starts.iter().any(Option::is_none) || errors == 0,
            "{name}: cycle {k}"
        );
        cycles.push(starts);
    }
    let hit = cycles
        .iter()
        .filter(|c| c.iter().any(Option::is_none))
        .count();
    assert!(sim.stats().collisions >= hit as u64, "{name}");
    let m = sim.chip_mut(0).expect("master");
    for s in 1..=usize::from(slaves) {
        let h = rx_header(m, plan.master_at_header[s - 1]);
        let missed = cycles.iter().filter(|c| c[s - 1].is_none()).count();
        let last = cycles.last().is_some_and(|c| c[s - 1].is_some());
        assert_eq!(usize::from(h.nerr), missed, "{name}: AT {s} {h:?}");
        assert_eq!(h.rerr, !last, "{name}: AT {s} {h:?}");
        let at = plan.master_at_data[s - 1].expect("stored");
        let want = if missed < usize::from(CYCLES) {
            at_pattern(s, 0)
        } else {
            0
        };
        assert_eq!(m.read_ram(at), want, "{name}: AT {s} data");
    }
    cycles
}

/// Runs the case and checks it ([`seen_per_cycle`]).
fn check_case(c: &Case) -> Outcome {
    let (mut sim, log, plan, _) = overlap_run(c.d_us, c.ppm, Delivery::Fast);
    let name = format!("d {} µs, {} ppm", c.d_us, c.ppm);
    let cycles = seen_per_cycle(&mut sim, &log, &plan, 2, &name)
        .into_iter()
        .map(|c| {
            let (a, b) = (c[0], c[1]);
            let offset = a
                .zip(b)
                .map(|(a, b)| i64::try_from(b).expect("fits") - i64::try_from(a).expect("fits"));
            ([a.is_some(), b.is_some()], offset)
        })
        .collect();
    Outcome {
        cycles,
        collisions: sim.stats().collisions,
    }
}

/// Finds, by bisection on slave 2's clock error at `d_us` (slow: its AT later), the last
/// case where `before` holds and the first where it does not.
fn boundary(d_us: u16, before: impl Fn(&Simulation, &[Line]) -> bool) -> (Case, Case) {
    let (mut lo, mut hi) = (0.0f64, -20_000.0f64);
    let holds = |p: f64| {
        let (sim, log, _, _) = overlap_run(d_us, p, Delivery::Fast);
        before(&sim, &log)
    };
    assert!(holds(lo) && !holds(hi), "bracket at {d_us} µs");
    for _ in 0..40 {
        let mid = (lo + hi) / 2.0;
        if holds(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (Case { d_us, ppm: lo }, Case { d_us, ppm: hi })
}

// 410B §1 Fig. 4 (RS-485 bus); spec-notes "RS-485 bus": a telegram starting while another is
// on the bus garbles both from the first whole bit they share; a start within the other's
// last bit, or an overlap within the later one's sync word where the levels agree, is
// reported but garbles nothing; telegrams that only touch are clean.
#[test]
fn overlapping_transmissions_are_garbled_and_reported_touching_ones_are_not() {
    let cycles = usize::from(CYCLES);
    // Whole (same start), at the start, in the middle, near the end of slave 1's AT: every
    // cycle garbled, both ATs lost, each collision reported.
    for d in [0u16, 1, 3, 6, 9] {
        let o = check_case(&Case { d_us: d, ppm: 0.0 });
        assert_eq!(
            (o.garbled(), o.collisions),
            (cycles, CYCLES.into()),
            "d {d}"
        );
    }
    // 10 µs: slave 2's sync word meets slave 1's closing flag only: reported, both received.
    let o = check_case(&Case { d_us: 10, ppm: 0.0 });
    assert!(o.whole() && o.collisions == u64::from(CYCLES));
    // Where garbling ends: the last case with a garbled cycle and the first without one
    // are both reported in every cycle.
    let garbled = |_: &Simulation, log: &[Line]| log.iter().any(|l| !l.ok);
    let (last_garbled, first_whole) = boundary(9, garbled);
    let o = check_case(&last_garbled);
    assert!(o.cycles.iter().any(|c| c.0 != [true, true]));
    assert_eq!(o.collisions, u64::from(CYCLES));
    let o = check_case(&first_whole);
    assert!(o.whole() && o.collisions == u64::from(CYCLES));
    // Where overlapping ends (slave 1's AT ends between 10 and 14 µs after its start).
    let d = (10..14)
        .find(|&d| overlap_run(d + 1, 0.0, Delivery::Fast).0.stats().collisions == 0)
        .expect("a clean offset");
    let collides = |sim: &Simulation, _: &[Line]| sim.stats().collisions > 0;
    let (last, first) = boundary(d, collides);
    let (last, first) = (check_case(&last), check_case(&first));
    assert!(last.whole() && first.whole() && last.collisions > 0 && first.collisions == 0);
    // Per cycle (the chips start on their own clock edges, so the offset varies a little):
    // the reported cycles are the earliest starts, none after a clean one, less than a bit
    // apart (an overlap of less than one bit is reported, a telegram touching the end is
    // not; a reported telegram joins the line's bit grid, up to a bit later, so it may log
    // the start of the first clean one).
    let mut all = last.offsets();
    all.sort_unstable();
    let n = usize::try_from(last.collisions).expect("fits");
    let max_reported = all[n - 1];
    let min_clean = all[n..]
        .iter()
        .chain(&first.offsets())
        .copied()
        .min()
        .expect("clean");
    assert!(
        max_reported <= min_clean && min_clean - all[0] < i64::try_from(BIT_PS).expect("fits"),
        "{max_reported} {min_clean}"
    );
    // Well apart.
    let o = check_case(&Case { d_us: 20, ppm: 0.0 });
    assert!(o.whole() && o.collisions == 0);
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

// 410B §1 Fig. 4; spec-notes "RS-485 bus": three ATs on top of one another (slave 2's and
// slave 3's laid onto the line slave 1's began, the third onto a line already garbled) or
// in a chain (2 overlaps 1, 3 overlaps 2): the master's view is still what the line shows,
// cycle by cycle, and three that overlap on whole bits are all lost.
#[test]
fn three_overlapping_ats_leave_the_master_seeing_what_the_line_shows() {
    let t = bus_ring(3).build().expect("fits").2.at_trt_us[0];
    for (d2, d3, lost) in [
        (1u16, 2u16, true),
        (2, 5, true),
        (0, 0, true),
        (6, 12, false),
        (3, 9, false),
    ] {
        let mut ring = bus_ring(3);
        ring.at_trt_override = Some(vec![t + 40, t + 40 + d2, t + 40 + d3]);
        let (mut sim, log, plan, _) = run_bus(&ring, Duration::from_nanos(50), &[], RUN_US);
        let name = format!("ATs 2 and 3 at +{d2} and +{d3} µs");
        let cycles = seen_per_cycle(&mut sim, &log, &plan, 3, &name);
        assert!(sim.stats().collisions >= u64::from(CYCLES), "{name}");
        if lost {
            assert!(
                cycles.iter().flatten().all(Option::is_none),
                "{name}: {cycles:?}"
            );
        }
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

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(16)))]

    // 410B §4.2.1 (RERR, NERR, VAL); spec-notes "RS-485 bus": for any overlap of slave 2's
    // AT with slave 1's (its TRT and clock error), the master's view of both ATs is what the
    // bus log shows intact, cycle by cycle, and every cycle that loses an AT counts a
    // collision (`check_case`); no panic.
    #[test]
    fn any_overlap_leaves_the_master_seeing_what_the_line_shows(
        d_us in 0u16..=14,
        ppm in -20_000.0f64..0.0,
    ) {
        check_case(&Case { d_us, ppm });
    }
}
