//! The simulator's short paths (`Simulation::short_paths`: a woken node's wake not set
//! twice, `rewake_done`) against the same rings without them: the same
//! telegrams on every fibre, the same counters (events too), every chip the same after
//! every step, intact and with every kind of fault.

use sercos_wire::time::Instant;

use super::SimStats;
use super::run_ahead_tests::{STEP, Watch, any_fault, run_with, six_slaves, us};
use crate::fault::{Fault, FaultKind};
use crate::host::HostProgram;
use crate::static_ring::StaticRing;

/// Runs `ring` with and without the short paths, in steps of [`STEP`] and in one run, logged
/// and quiet, and asserts the same outcome; returns the quiet one-run counters.
fn same_either_way(ring: &StaticRing, faults: &[Fault], until: Instant, what: &str) -> SimStats {
    let whole = until.saturating_duration_since(Instant::ZERO);
    let wrap = |_: usize, h: Box<dyn HostProgram>| h;
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
            assert_eq!(long.stats, short.stats, "{what}: counters");
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
    assert!(quiet.ats_sent_on >= 6 * 4, "{quiet:?}");
    let mut long = StaticRing::new(20, 2000);
    long.bit_rate = sercos_wire::time::BitRate::Mbit4;
    let quiet = same_either_way(&long, &[], us(10_000), "20 slaves at 4 Mbit/s");
    assert!(quiet.ats_sent_on >= 20 * 3, "{quiet:?}");
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
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]

    // Any small ring (ATs anywhere after the MST) with up to three faults of any kind:
    // the same run with the short paths as without.
    #[test]
    fn any_ring_and_faults_run_the_same_without_the_short_paths(
        slaves in 1usize..=6,
        cycle_us in 250u16..=500,
        words in 1u16..=3,
        fibre_m in 1u32..=200,
        faults in proptest::collection::vec(
            (0u8..6, 0usize..8, 200u64..1300, 1u64..400), 0..=3),
        trts in proptest::option::of(proptest::collection::vec(5u16..150, 6)),
    ) {
        let mut ring = StaticRing::new(slaves, cycle_us);
        ring.mdt_words = words;
        ring.at_words = words;
        ring.fibre_m = fibre_m;
        ring.at_trt_override = trts;
        proptest::prop_assume!(ring.build().is_ok());
        let faults: Vec<Fault> = faults
            .into_iter()
            .map(|(kind, k, at, len)| any_fault(kind, k, at, len, slaves + 1))
            .collect();
        same_either_way(&ring, &faults, us(1300), "any ring");
    }
}

// A node whose wake its own wake set after its input (`rewake_done`) gets more input in the
// same event: it goes back on the list, so its wake is found again after that input.
#[test]
fn input_after_a_woken_node_set_its_wake_puts_it_back() {
    use sercon_model::serial_port::{LineSegment, LineSignal};
    use sercos_wire::time::Duration;

    let Ok((cfg, hosts, _)) = six_slaves().build() else {
        panic!("the ring fits");
    };
    let Ok(mut sim) = super::Simulation::new(cfg, hosts) else {
        panic!("the simulation builds");
    };
    assert!(sim.run_until(us(700)).is_ok());
    let Some(master) = sim.nodes.first() else {
        panic!("a master");
    };
    assert!(master.quiet_host(), "the static master's host is quiet");
    let at = master.chip.now().saturating_add(Duration::from_micros(1));
    // As `wake_node` leaves it: marked, off the list.
    sim.is_rewake[0] = true;
    sim.rewake_done = 0;
    let filler = LineSegment::steady(at, Duration::from_nanos(62), LineSignal::Filler, false);
    sim.deliver(0, filler, 1, false);
    assert_eq!(sim.rewake, vec![0], "back on the list");
    assert_eq!(sim.rewake_done, super::NO_NODE);
    sim.set_rewakes();
    assert!(!sim.is_rewake[0] && sim.rewake.is_empty());
}
