//! The simulator's short paths (`Simulation::short_paths`: a woken node's wake not set
//! twice, `rewake_done`; the slaves whose ATs were sent on not served for nothing,
//! `early_route`'s `unserve_sent_on`) against the same rings without them: the same
//! telegrams on every fibre, the same counters (events too), every chip the same after
//! every step, intact and with every kind of fault.

use sercon_regs::SerconBus;
use sercon_regs::value::control::Ctrl3;
use sercon_regs::value::interrupt::IntFlagsLo;
use sercos_wire::time::Instant;

use super::SimStats;
use super::run_ahead_tests::{
    STEP, Watch, any_fault, any_ring_and_faults, run_with, six_slaves, us,
};
use crate::fault::{Fault, FaultKind};
use crate::host::{HostProgram, Wake};
use crate::static_ring::StaticRing;

/// A slave's static host that also enables INT0 on its own telegram's end (410B §4.1 6H
/// INT_TEND, 3H ENINT0) and clears every flag of 4H when woken for it: its chip's INT0 rises
/// inside a run past its AT, so the slave is not quiet when its AT is sent on. It calls
/// itself inert so that slaves still run ahead: the runs with and without the short paths
/// must still agree.
struct Clearing(Box<dyn HostProgram>);

impl HostProgram for Clearing {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        let next = self.0.wake(bus, now, why);
        match why {
            Wake::Start | Wake::PowerOn => {
                bus.write_register(6, IntFlagsLo::INT_TEND.bits());
                let r3 = bus.read_register(3);
                bus.write_register(3, r3 | Ctrl3::ENINT0.bits());
            }
            Wake::Interrupt { .. } => bus.write_register(4, 0xffff),
            _ => {}
        }
        next
    }

    fn inert(&self) -> bool {
        true
    }
}

/// Runs `ring` with and without the short paths, in steps of [`STEP`] and in one run, logged
/// and quiet, and asserts the same outcome; returns the quiet one-run counters.
fn same_either_way(ring: &StaticRing, faults: &[Fault], until: Instant, what: &str) -> SimStats {
    same_either_way_hosts(ring, faults, until, what, 0..0)
}

/// [`same_either_way`], the hosts of the nodes in `clearing` [`Clearing`].
fn same_either_way_hosts(
    ring: &StaticRing,
    faults: &[Fault],
    until: Instant,
    what: &str,
    clearing: std::ops::Range<usize>,
) -> SimStats {
    let whole = until.saturating_duration_since(Instant::ZERO);
    let wrap = |i: usize, h: Box<dyn HostProgram>| -> Box<dyn HostProgram> {
        if clearing.contains(&i) {
            Box::new(Clearing(h))
        } else {
            h
        }
    };
    let mut last = SimStats::default();
    for watch in [Watch::Logged, Watch::Quiet] {
        for step in [STEP, whole] {
            let run = |short: bool| {
                run_with(ring, faults, &wrap, watch, (step, until), &|sim| {
                    sim.short_paths = short;
                })
            };
            let (long, short) = (run(false), run(true));
            let what = format!("{what} ({watch:?}, steps of {step:?})");
            assert_eq!(long.log, short.log, "{what}: telegram log");
            // A wake joined to the one before (`sim/join_wake.rs`) is one event fewer.
            assert_eq!(long.stats.joined_wakes, 0, "{what}");
            let joined = SimStats {
                events: short.stats.events + short.stats.joined_wakes,
                joined_wakes: 0,
                ..short.stats
            };
            assert_eq!(long.stats, joined, "{what}: counters");
            assert_eq!(long.chips, short.chips, "{what}: registers and RAM");
            assert_eq!(long.steps, short.steps, "{what}: chips after every step");
            last = short.stats;
        }
    }
    last
}

#[test]
fn an_intact_ring_runs_the_same_without_the_short_paths() {
    let quiet = same_either_way(&six_slaves(), &[], us(1600), "6 slaves");
    // The ATs were sent on (the slaves then touched for nothing, `unserve_sent_on`).
    assert!(quiet.ats_sent_on >= 6 * 4, "{quiet:?}");
    // The master's MDT was taken in the wake of its MST (`sim/join_wake.rs`).
    assert!(quiet.joined_wakes >= 5, "{quiet:?}");
    let mut long = StaticRing::new(20, 2000);
    long.bit_rate = sercos_wire::time::BitRate::Mbit4;
    let quiet = same_either_way(&long, &[], us(10_000), "20 slaves at 4 Mbit/s");
    assert!(quiet.ats_sent_on >= 20 * 3, "{quiet:?}");
}

/// 410B §4.2.1 TRT: a slave whose AT lies between the MST and the MDT, the MDT close behind
/// (one slave, one data word each way, the MDT after the AT: ≈ 11 µs after the MST's end).
/// Its run ahead after the MST goes through its AT, which goes out at its time; no other
/// test ring has an AT there on the quiet fast path (docs/performance.md, session 13
/// "onepass": a check that told the MST's pass from the MDT's by the MDT's distance passed
/// every other test).
#[test]
fn an_at_between_the_mst_and_a_close_mdt_runs_the_same_without_the_short_paths() {
    let mut ring = StaticRing::new(1, 250);
    ring.mdt_after_ats = true;
    ring.mdt_words = 1;
    ring.at_words = 1;
    let quiet = same_either_way(&ring, &[], us(1600), "an AT before a close MDT");
    assert!(quiet.ats_sent_on >= 4, "{quiet:?}");
}

#[test]
fn slaves_with_interrupts_run_the_same_without_the_short_paths() {
    let quiet = same_either_way_hosts(
        &six_slaves(),
        &[],
        us(1600),
        "6 clearing slaves",
        1..usize::MAX,
    );
    assert!(quiet.ats_sent_on > 0, "{quiet:?}");
}

/// Slaves 2 to 4 take INT0 on their AT's end, the others are quiet: after the ATs are sent
/// on, only the quiet slaves leave the touched list (`unserve_sent_on`); the others are
/// served as they would be.
#[test]
fn some_slaves_with_interrupts_run_the_same_without_the_short_paths() {
    let quiet = same_either_way_hosts(&six_slaves(), &[], us(1600), "3 clearing slaves", 2..5);
    assert!(quiet.ats_sent_on > 0, "{quiet:?}");
}

/// Fibres of no length: the master's telegram reaches the first slave at its start, whose
/// run ahead then ends just before the master's next wake, and its wake comes first (the
/// master's next wake is not joined, `sim/join_wake.rs`).
#[test]
fn fibres_of_no_length_run_the_same_without_the_short_paths() {
    let mut ring = six_slaves();
    ring.fibre_m = 0;
    same_either_way(&ring, &[], us(1600), "6 slaves, no fibre length");
}

/// The master's host enables INT0 on its own telegrams' ends and clears the flags when woken
/// for it (410B §4.1 6H INT_TEND, 3H ENINT0): its chip's next output bound is then its next
/// internal event (`Chip::next_output_bound`), before its promised next telegram, and the
/// wakes between must not be joined away (`sim/join_wake.rs`).
#[test]
fn a_master_with_interrupts_runs_the_same_without_the_short_paths() {
    same_either_way_hosts(&six_slaves(), &[], us(1600), "a clearing master", 0..1);
}

#[test]
fn faults_run_the_same_without_the_short_paths() {
    for kind in 0u8..6 {
        for k in [0usize, 2, 4] {
            let f = any_fault(kind, k, 520, 330, 7);
            same_either_way(&six_slaves(), &[f], us(1500), &format!("fault {f:?}"));
        }
    }
    let power = Fault {
        at: us(600),
        kind: FaultKind::PowerOff {
            node: 3,
            until: Some(us(850)),
        },
    };
    same_either_way(&six_slaves(), &[power], us(1600), "power off and on");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(32)))]

    // Any small ring (ATs anywhere after the MST) with up to three faults of any kind:
    // the same run with the short paths as without.
    #[test]
    fn any_ring_and_faults_run_the_same_without_the_short_paths(
        (ring, faults) in any_ring_and_faults(),
    ) {
        same_either_way(&ring, &faults, us(1300), "any ring");
    }
}

// A node whose wake its own wake set after its input (`rewake_done`) gets more input in the
// same event: it goes back on the list, so its wake is found again after that input.
#[test]
fn input_after_a_woken_node_set_its_wake_puts_it_back() {
    use sercon_model::serial_port::{LineSegment, LineSignal};
    use sercos_wire::time::Duration;

    let mut sim = six_slaves_at_700_us();
    let Some(master) = sim.nodes.first() else {
        panic!("a master");
    };
    assert!(master.quiet_host(), "the static master's host is quiet");
    let at = master.chip.now().saturating_add(Duration::from_micros(1));
    // As `wake_node` leaves it: marked, off the list.
    if let Some(m) = sim.nodes.first_mut() {
        m.is_rewake = true;
    }
    sim.rewake_done = 0;
    let filler = LineSegment::steady(at, Duration::from_nanos(62), LineSignal::Filler, false);
    sim.deliver(0, filler, 1, false);
    assert_eq!(sim.rewake, vec![0], "back on the list");
    assert_eq!(sim.rewake_done, super::NO_NODE);
    sim.set_rewakes();
    assert!(sim.nodes.first().is_some_and(|m| !m.is_rewake) && sim.rewake.is_empty());
}

// `route_taken` sends a take of several segments on as one `route_output` each, in order
// (the usual take, one segment, is popped; the rest drained).
#[test]
fn a_take_of_several_segments_goes_on_in_order() {
    use sercon_model::serial_port::{LineSegment, LineSignal};
    use sercos_wire::time::Duration;

    let build = six_slaves_at_700_us;
    // Two and three segments: both go past the one-segment pop.
    for n in [2, 3] {
        let (mut taken, mut each) = (build(), build());
        let Some(slave) = taken.nodes.get(1) else {
            panic!("a slave");
        };
        let at = slave.chip.now().saturating_add(Duration::from_micros(1));
        let bit = Duration::from_nanos(62);
        let segs = [
            LineSegment::steady(at, bit, LineSignal::Dark, false),
            LineSegment::steady(at.saturating_add(bit), bit, LineSignal::Light, false),
            LineSegment::steady(
                at.saturating_add(bit.saturating_mul(3)),
                bit,
                LineSignal::Filler,
                false,
            ),
        ];
        let segs = segs.get(3 - n..).unwrap_or_default();
        let mut out = segs.to_vec();
        taken.route_taken(1, &mut out);
        assert!(out.is_empty(), "every segment sent on");
        for s in segs {
            each.route_output(1, s.clone());
        }
        assert!(taken.run_until(us(900)).is_ok() && each.run_until(us(900)).is_ok());
        assert_eq!(taken.stats, each.stats, "{n} segments: counters");
        assert_eq!(
            super::test_state::chip_words(&mut taken, 64),
            super::test_state::chip_words(&mut each, 64),
            "{n} segments: registers and RAM"
        );
    }
}

/// 410B §4.2.1 TRT (the master's promise), §1 (repeaters): the master's clock drifts from
/// 400 µs on, so its promise no longer holds for the slaves (`Simulation::master_horizon`:
/// on the simulation's clock only), while its telegrams still sweep the plain slaves
/// (`sim/swept.rs`): each runs ahead only to the end of the telegram and its wake after it.
/// Debug builds compare every swept delivery's horizon with `master_horizon`'s (a sweep that
/// took the promise as holding whatever the master's clock fails here).
#[test]
fn a_drifting_master_runs_the_same_without_the_short_paths() {
    let drift = Fault {
        at: us(400),
        kind: FaultKind::ClockDrift { node: 0, ppm: 60.0 },
    };
    let quiet = same_either_way(&six_slaves(), &[drift], us(1600), "a drifting master");
    // Before the drift the slaves ran past their ATs; after it only to the telegrams' ends.
    assert!(quiet.runs_past_output > 0, "{quiet:?}");
    assert!(
        quiet.run_aheads > quiet.runs_past_output + 6 * 2 * 3,
        "{quiet:?}"
    );
}

/// A slave whose pins are traced (a VCD) has no quiet host (`Node::quiet_host`): it runs
/// not ahead when the master's telegram sweeps past it (`sim/swept.rs`), the others do. The
/// same run, traced pins included, with the short paths as without.
#[test]
fn a_sweep_past_a_traced_slave_runs_the_same_without_the_short_paths() {
    use sercon_model::pins::PinSet;
    use sercos_wire::time::Duration;

    let run = |short: bool, step: Duration| {
        let Ok((mut cfg, hosts, _)) = six_slaves().build() else {
            panic!("the ring fits");
        };
        cfg.traces.vcd = vec![(3, PinSet::ALL)];
        let Ok(mut sim) = super::Simulation::new(cfg, hosts) else {
            panic!("the simulation builds");
        };
        sim.short_paths = short;
        let mut t = Instant::ZERO;
        while t < us(1600) {
            t = t.saturating_add(step).min(us(1600));
            assert!(sim.run_until(t).is_ok());
        }
        let stats = sim.stats();
        let words = super::test_state::chip_words(&mut sim, 2048);
        let Ok(out) = sim.finish() else {
            panic!("the traces end");
        };
        (stats, words, out.vcd)
    };
    for step in [STEP, Duration::from_micros(1600)] {
        let (long, short) = (run(false, step), run(true, step));
        let joined = SimStats {
            events: short.0.events + short.0.joined_wakes,
            joined_wakes: 0,
            ..short.0
        };
        assert_eq!(long.0, joined, "counters (steps of {step:?})");
        assert_eq!(long.1, short.1, "registers and RAM (steps of {step:?})");
        assert_eq!(long.2, short.2, "traced pins (steps of {step:?})");
        // Its pins change (a VCD's `#` time stamps).
        assert!(
            short.2.iter().filter(|b| **b == b'#').count() > 10,
            "pins traced"
        );
        // The five other slaves ran past their ATs.
        assert!(short.0.runs_past_output >= 5 * 2 * 4, "{:?}", short.0);
    }
}

/// A slave's delivery in a sweep of the master's segment (`sim/swept.rs`) against `deliver`
/// itself, each on its own copy of one ring at 700 µs: the master's bits with their filler
/// ahead of the slave's chip, its bits starting before the receiver's input floor (cut there,
/// `out_of_order`: the sweep hands them to `deliver`), a filler (continued from the bits
/// before, `Node::continue_filler`: the same). The slave ends the same either way (input
/// floor, counters, what is left to serve or set, registers and RAM), and so does the run
/// after it.
#[test]
fn a_swept_delivery_is_deliver_s_own() {
    use sercon_model::serial_port::{LineSegment, LineSignal, REPEATER_LATENCY_BITS};
    use sercos_wire::line::BitVec;
    use sercos_wire::time::Duration;

    let build = six_slaves_at_700_us;
    // 16 Mbit/s (the ring's rate): 62.5 ns a bit.
    let bit = Duration::from_picos(62_500);
    let bits_at = |start: Instant, n: usize, bit: Duration| {
        let mut v = BitVec::with_capacity(n);
        for i in 0..n {
            v.push(i % 3 == 0);
        }
        LineSegment {
            then_filler: true,
            ..LineSegment::bits(start, bit, v, false)
        }
    };
    let bits = |start: Instant, n: usize| bits_at(start, n, bit);
    let probe = build();
    let Some(slave) = probe.nodes.get(1) else {
        panic!("a slave");
    };
    let (now, floor) = (slave.chip.now(), slave.in_floor);
    assert!(floor > us(1), "the slave had input");
    // The end of the bits it received last, and the level they left (410B §4.1 1H.12 NRZI).
    let (Some(end), Some(level)) = (
        slave.chip.last_input_bits_end(),
        slave
            .chip
            .last_input_bits_end()
            .and_then(|e| slave.chip.received_level_at(e)),
    ) else {
        panic!("the slave received bits");
    };
    let segs = [
        (
            "bits ahead",
            bits(now.saturating_add(Duration::from_micros(2)), 64),
        ),
        (
            "bits out of order",
            bits(Instant::from_picos(floor.as_picos() - 1_000_000), 400),
        ),
        (
            "filler",
            LineSegment::steady(
                now.saturating_add(Duration::from_micros(3)),
                bit,
                LineSignal::Filler,
                false,
            ),
        ),
        // Another bit time, another repeater latency (410B §1): the sweep's table of the
        // master's reach is made anew (`master_reach`).
        (
            "bits at 8 Mbit/s",
            bits_at(
                now.saturating_add(Duration::from_micros(2)),
                64,
                bit.saturating_mul(2),
            ),
        ),
        // Sent from the other level: taken on from the bits' (`Node::continue_filler`).
        (
            "filler after the bits",
            LineSegment::steady(end, bit, LineSignal::Filler, !level),
        ),
    ];
    for (what, seg) in segs {
        let (mut swept, mut general) = (build(), build());
        // The repeater latency at the segment's bit time (410B §1), as a sweep takes it.
        let lat = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        let sw = swept.swept(&seg, lat);
        swept.deliver_swept(1, seg.clone(), &sw);
        general.deliver(1, seg, 0, true);
        let floors = |s: &super::Simulation| s.nodes.get(1).map(|n| n.in_floor);
        assert_eq!(floors(&swept), floors(&general), "{what}: input floor");
        // The line as the receiver saw it, a bit time after another.
        let levels = |s: &super::Simulation| {
            (0..16)
                .map(|k| {
                    let t = end.saturating_add(bit.saturating_mul(k));
                    s.nodes.get(1).and_then(|n| n.chip.received_level_at(t))
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(levels(&swept), levels(&general), "{what}: received levels");
        assert_eq!(swept.stats, general.stats, "{what}: counters");
        assert_eq!(swept.touched, general.touched, "{what}: touched");
        assert_eq!(swept.rewake, general.rewake, "{what}: wakes to set");
        assert_eq!(swept.deferred, general.deferred, "{what}: ATs deferred");
        assert_eq!(
            super::test_state::chip_words(&mut swept, 2048),
            super::test_state::chip_words(&mut general, 2048),
            "{what}: registers and RAM"
        );
        assert!(swept.run_until(us(900)).is_ok() && general.run_until(us(900)).is_ok());
        assert_eq!(swept.stats, general.stats, "{what}: counters after");
        assert_eq!(
            super::test_state::chip_words(&mut swept, 2048),
            super::test_state::chip_words(&mut general, 2048),
            "{what}: registers and RAM after"
        );
    }
}

/// [`six_slaves`] built, not run.
fn six_slaves_built() -> super::Simulation {
    let Ok((cfg, hosts, _)) = six_slaves().build() else {
        panic!("the ring fits");
    };
    let Ok(sim) = super::Simulation::new(cfg, hosts) else {
        panic!("the simulation builds");
    };
    sim
}

/// [`six_slaves`] built and run to 700 µs (steady, with ATs on the way).
fn six_slaves_at_700_us() -> super::Simulation {
    let mut sim = six_slaves_built();
    assert!(sim.run_until(us(700)).is_ok());
    sim
}

// `put_buf` lets the vector left in the take buffer's place go without the drop glue only
// when it holds no allocation (the empty one `mem::take` put there); one with an
// allocation is dropped (debug builds check that nothing allocated is let go).
#[test]
fn a_take_buffer_with_an_allocation_left_in_its_place_is_dropped() {
    let mut sim = six_slaves_built();
    sim.buf = Vec::with_capacity(4);
    sim.put_buf(Vec::new());
    assert_eq!(sim.buf.capacity(), 0, "the new buffer is in place");
    sim.put_buf(Vec::with_capacity(2));
    assert!(sim.buf.capacity() >= 2, "the new buffer is in place");
}
