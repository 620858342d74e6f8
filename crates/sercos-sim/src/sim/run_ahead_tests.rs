//! Slaves run ahead ([`Simulation::run_ahead`]) against the same ring without: the same
//! telegrams on every fibre, the same counters, the same registers and RAM in every chip,
//! with every kind of fault, on the static rings whose hosts are inert.

use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

use super::test_state::chip_words;
use super::{SimStats, Simulation};
use crate::fault::{Fault, FaultKind};
use crate::host::{HostProgram, Wake};
use crate::static_ring::StaticRing;
use crate::trace::LogFormat;

pub(super) fn us(n: u64) -> Instant {
    Instant::ZERO + Duration::from_micros(n)
}

/// RAM words read back from every chip (816 §2.5: 2048 words at most).
const RAM_WORDS: u16 = 2048;

/// A static ring's host that also reads 2H and 3H at every interrupt and every 37 µs: not
/// inert, so nothing runs ahead.
struct Polling(Box<dyn HostProgram>);

impl HostProgram for Polling {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        self.0.wake(bus, now, why);
        if matches!(why, Wake::Interrupt { .. } | Wake::Deadline) {
            bus.read_register(3);
            bus.read_register(2);
        }
        Some(now.saturating_add(Duration::from_micros(37)))
    }
}

/// What a run leaves: the text log of every fibre, the counters, and every chip's
/// registers 0H–1FH and RAM at the end; every chip's time and registers after every step.
pub(super) struct Outcome {
    pub(super) log: String,
    pub(super) stats: SimStats,
    pub(super) chips: Vec<u16>,
    pub(super) steps: Vec<(Vec<Instant>, Vec<u16>)>,
}

/// Steps of `run_until` (a chip read after a run is at its end, run ahead or not).
pub(super) const STEP: Duration = Duration::from_micros(7);

/// How a run is watched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Watch {
    /// Every fibre's telegrams logged (a traced fibre carries a telegram and its filler
    /// apart, so slaves run ahead only to the end of the master's telegram).
    Logged,
    /// Nothing logged: the master's telegrams carry their filler to every slave, which then
    /// run through their own telegrams up to the master's next one
    /// ([`Simulation::master_horizon`]).
    Quiet,
}

/// Runs `ring` to `until` in steps of `step` with `faults`, slaves running ahead or not,
/// every host wrapped in [`Polling`] if `polling`.
fn run(
    ring: &StaticRing,
    faults: &[Fault],
    (ahead, polling): (bool, bool),
    watch: Watch,
    steps: (Duration, Instant),
) -> Outcome {
    let wrap = |_: usize, h: Box<dyn HostProgram>| -> Box<dyn HostProgram> {
        if polling { Box::new(Polling(h)) } else { h }
    };
    run_with(ring, faults, &wrap, watch, steps, &|sim| {
        sim.run_ahead_ok &= ahead;
    })
}

/// [`run`] with node `i`'s host given by `wrap(i, host)` and `configure` applied to the
/// simulation before it runs.
pub(super) fn run_with(
    ring: &StaticRing,
    faults: &[Fault],
    wrap: &dyn Fn(usize, Box<dyn HostProgram>) -> Box<dyn HostProgram>,
    watch: Watch,
    (step, until): (Duration, Instant),
    configure: &dyn Fn(&mut Simulation),
) -> Outcome {
    let Ok((mut cfg, hosts, _)) = ring.build() else {
        panic!("the ring fits");
    };
    if watch == Watch::Logged {
        cfg.traces.log = Some(LogFormat::Text);
    }
    cfg.faults = faults.to_vec();
    let hosts: Vec<Box<dyn HostProgram>> = hosts
        .into_iter()
        .enumerate()
        .map(|(i, h)| wrap(i, h))
        .collect();
    let Ok(mut sim) = Simulation::new(cfg, hosts) else {
        panic!("the simulation builds");
    };
    configure(&mut sim);
    let mut steps = Vec::new();
    let mut t = Instant::ZERO;
    while t < until {
        t = t.saturating_add(step).min(until);
        assert!(sim.run_until(t).is_ok());
        let nows = (0..sim.node_count())
            .filter_map(|j| sim.chip_mut(j).map(|c| c.now()))
            .collect();
        steps.push((nows, chip_words(&mut sim, 0)));
    }
    let stats = sim.stats();
    let chips = chip_words(&mut sim, RAM_WORDS);
    let Ok(out) = sim.finish() else {
        panic!("the traces end");
    };
    Outcome {
        log: String::from_utf8_lossy(&out.log).into_owned(),
        stats,
        chips,
        steps,
    }
}

/// Both ways give the same run, logged and quiet; returns the counters of the logged and
/// the quiet run ahead.
fn same_run(
    ring: &StaticRing,
    faults: &[Fault],
    until: Instant,
    what: &str,
) -> (SimStats, SimStats) {
    (
        same_run_watched(ring, faults, until, what, Watch::Logged),
        same_run_watched(ring, faults, until, what, Watch::Quiet),
    )
}

/// [`same_run`] one way of watching: in steps of [`STEP`] (every chip compared after each)
/// and in one run to `until` (where a run ahead is bound by the master's next telegram, not
/// by the step's end); returns the counters of the one run ahead.
fn same_run_watched(
    ring: &StaticRing,
    faults: &[Fault],
    until: Instant,
    what: &str,
    watch: Watch,
) -> SimStats {
    let whole = until.saturating_duration_since(Instant::ZERO);
    same_run_stepped(ring, faults, (STEP, until), what, watch);
    same_run_stepped(ring, faults, (whole, until), what, watch)
}

/// [`same_run_watched`] in steps of `step`.
fn same_run_stepped(
    ring: &StaticRing,
    faults: &[Fault],
    steps: (Duration, Instant),
    what: &str,
    watch: Watch,
) -> SimStats {
    let plain = run(ring, faults, (false, false), watch, steps);
    let ahead = run(ring, faults, (true, false), watch, steps);
    let what = format!("{what} ({watch:?}, steps of {:?})", steps.0);
    assert_eq!(
        !plain.log.is_empty(),
        watch == Watch::Logged,
        "{what}: a log"
    );
    assert_eq!(plain.log, ahead.log, "{what}: telegram log");
    assert_eq!(plain.stats.run_aheads, 0, "{what}");
    // A slave run ahead wakes when its output starts; without, it may also wake at a bound
    // its run would have moved on (a block's start, an AT header reached only after the
    // MDT's): the wakes may differ, nothing the ring does.
    assert_eq!(
        SimStats {
            events: plain.stats.events,
            run_aheads: 0,
            runs_past_output: 0,
            ats_sent_on: 0,
            parked_wakes: 0,
            joined_wakes: 0,
            ..ahead.stats
        },
        plain.stats,
        "{what}: counters"
    );
    assert_eq!(plain.chips, ahead.chips, "{what}: registers and RAM");
    assert_eq!(plain.steps.len(), ahead.steps.len());
    for (k, (p, a)) in plain.steps.iter().zip(&ahead.steps).enumerate() {
        assert_eq!(p, a, "{what}: chips after step {k}");
    }
    ahead.stats
}

pub(super) fn six_slaves() -> StaticRing {
    let mut ring = StaticRing::new(6, 250);
    ring.fibre_m = 30;
    ring.mdt_words = 2;
    ring.at_words = 2;
    ring
}

#[test]
fn an_intact_ring_runs_the_same_with_slaves_ahead() {
    let (logged, quiet) = same_run(&six_slaves(), &[], us(1600), "6 slaves");
    // Two telegrams of the master (MST, MDT) per slave and cycle, from phase 4 on; logged,
    // each run stops before the telegram's end, quiet, each goes to the master's next one
    // (past the slave's AT after the MDT).
    for s in [logged, quiet] {
        assert!(s.run_aheads >= 6 * 2 * 4, "the slaves ran ahead: {s:?}");
    }
    assert_eq!(logged.runs_past_output, 0);
    assert!(quiet.runs_past_output >= 6 * 2 * 4, "{quiet:?}");
    // Every AT of the steady cycles sent on right after the MDT (`early_route`).
    assert_eq!(logged.ats_sent_on, 0);
    assert!(quiet.ats_sent_on >= 6 * 4, "{quiet:?}");
    // After each such run the slave's wake is parked at its chip's time (`park`) rather
    // than found; the run is the same (above).
    assert_eq!(logged.parked_wakes, 0);
    assert!(quiet.parked_wakes >= 6 * 2 * 4, "{quiet:?}");
    let mut long = StaticRing::new(20, 2000);
    long.bit_rate = sercos_wire::time::BitRate::Mbit4;
    let (logged, quiet) = same_run(&long, &[], us(10_000), "20 slaves at 4 Mbit/s");
    for s in [logged, quiet] {
        assert!(s.run_aheads >= 20 * 2 * 3, "the slaves ran ahead: {s:?}");
    }
    assert!(quiet.runs_past_output >= 20 * 2 * 3, "{quiet:?}");
    assert!(quiet.ats_sent_on >= 20 * 3, "{quiet:?}");
}

// 410B §4.2.1 TRT: with the ATs before the MDT (MST, AT 1 … AT n, MDT, the order the
// master driver plans) each slave runs, after the MST, past its own AT up to the MDT, and the
// ATs are sent on right after the MST's pass (`early_route`: for ATs a slave's list puts
// before the MDT's receive header); the run is the same as without running ahead.
#[test]
fn the_mdt_after_the_ats_runs_the_same_with_slaves_ahead() {
    let mut ring = six_slaves();
    ring.mdt_after_ats = true;
    let (logged, quiet) = same_run(&ring, &[], us(1600), "6 slaves, MDT after the ATs");
    // Six cycles and a bit: from the first cycle on, every slave's AT each cycle.
    assert!(quiet.runs_past_output >= 6 * 2 * 5, "{quiet:?}");
    assert!(quiet.ats_sent_on >= 6 * 5, "{quiet:?}");
    assert!(quiet.events * 2 <= logged.events, "{logged:?} {quiet:?}");
    assert_eq!(logged.ats_sent_on, 0);
}

// 410B §1 (repeaters), §4.2.1 TRT: on 2 km fibres with the MDT after the ATs, slaves 2 and
// 3 start their ATs after the master has started its MDT but before it reaches them (5 and
// 25 µs after its start; it reaches them 20 and 30 µs after it). Every slave's AT is then
// queued when the MST's pass ends: the run is the same as without running ahead.
#[test]
fn ats_started_after_the_master_s_next_telegram_run_the_same_with_slaves_ahead() {
    let mut ring = StaticRing::new(3, 500);
    ring.fibre_m = 2000;
    ring.mdt_words = 1;
    ring.at_words = 1;
    ring.mdt_after_ats = true;
    let Ok((_, _, plan)) = ring.build() else {
        panic!("the ring fits");
    };
    let mut trts = plan.at_trt_us.clone();
    trts[1] = plan.mdt_trt_us - 15;
    trts[2] = plan.mdt_trt_us - 5;
    ring.at_trt_override = Some(trts);
    let (_, quiet) = same_run(&ring, &[], us(3000), "3 slaves, ATs after the MDT's start");
    assert!(quiet.runs_past_output >= 3 * 4, "{quiet:?}");
    // `deferred_may_go` sends ATs on only when each starts before the master's next
    // telegram: none here. (Without that rule these ATs are sent on, 15 of them, and the run
    // is still the same, also with slave 3's AT overlapping the MDT's arrival: the rule is
    // conservative; spec-notes "ATs sent on".)
    assert_eq!(quiet.ats_sent_on, 0, "{quiet:?}");
}

#[test]
fn faults_give_the_same_run_with_slaves_ahead() {
    let faults = [
        (
            "fibre break and repair",
            vec![Fault {
                at: us(520),
                kind: FaultKind::FibreBreak {
                    segment: 2,
                    until: Some(us(910)),
                },
            }],
        ),
        (
            "bit errors",
            vec![Fault {
                at: us(300),
                kind: FaultKind::BitErrors {
                    segment: 1,
                    until: us(1400),
                    rate: 2e-3,
                },
            }],
        ),
        (
            "burst",
            vec![Fault {
                at: us(610),
                kind: FaultKind::BitErrorBurst {
                    segment: 0,
                    bits: 40,
                },
            }],
        ),
        (
            "power off and on",
            vec![Fault {
                at: us(600),
                kind: FaultKind::PowerOff {
                    node: 3,
                    until: Some(us(850)),
                },
            }],
        ),
        (
            "clock drift",
            vec![Fault {
                at: us(400),
                kind: FaultKind::ClockDrift { node: 4, ppm: 80.0 },
            }],
        ),
        (
            "distortion",
            vec![Fault {
                at: us(700),
                kind: FaultKind::Distortion {
                    segment: 5,
                    until: us(1100),
                },
            }],
        ),
    ];
    for (what, f) in faults {
        let (logged, quiet) = same_run(&six_slaves(), &f, us(1600), what);
        // Faults that cut the line turn running ahead off (their dark could cut a
        // telegram a slave already ran through: spec-notes "Slaves run ahead").
        if matches!(what, "fibre break and repair" | "power off and on") {
            assert_eq!(logged.run_aheads + quiet.run_aheads, 0, "{what}");
            continue;
        }
        assert!(logged.run_aheads > 0, "{what}: the slaves ran ahead");
        // A burst scheduled on the master's own fibre leaves it faulty for the whole run:
        // the master's telegrams reach the slaves without their filler.
        assert!(
            quiet.runs_past_output > 0 || what == "burst",
            "{what}: and past their output"
        );
    }
}

#[test]
fn nothing_runs_ahead_of_a_host_that_reads_its_chip() {
    let ring = six_slaves();
    let polled = run(&ring, &[], (true, true), Watch::Quiet, (STEP, us(1600)));
    assert_eq!(polled.stats.run_aheads, 0);
    assert!(polled.stats.deliveries > 0);
}

/// One fault of any kind at `at_us` on segment or node `k` (taken modulo the ring's).
pub(super) fn any_fault(kind: u8, k: usize, at_us: u64, len_us: u64, nodes: usize) -> Fault {
    let at = us(at_us);
    let until = us(at_us + len_us);
    let seg = k % nodes;
    let slave = 1 + k % (nodes - 1);
    let kind = match kind % 6 {
        0 => FaultKind::FibreBreak {
            segment: seg,
            until: Some(until),
        },
        1 => FaultKind::BitErrors {
            segment: seg,
            until,
            rate: 1e-3,
        },
        2 => FaultKind::BitErrorBurst {
            segment: seg,
            bits: 1 + (len_us % 60) as u32,
        },
        3 => FaultKind::PowerOff {
            node: slave,
            until: Some(until),
        },
        4 => FaultKind::ClockDrift {
            node: slave,
            ppm: len_us as f64 - 100.0,
        },
        _ => FaultKind::Distortion {
            segment: seg,
            until,
        },
    };
    Fault { at, kind }
}

/// Any small ring, its ATs where the layout puts them or anywhere after the MST (on top of
/// the MDT and of each other), with up to three faults of any kind at any time: the input of
/// the property tests that run a ring two ways.
pub(super) fn any_ring_and_faults()
-> impl proptest::strategy::Strategy<Value = (StaticRing, Vec<Fault>)> {
    use proptest::prelude::*;
    (
        1usize..=6,
        250u16..=500,
        1u16..=3,
        1u32..=200,
        proptest::collection::vec((0u8..6, 0usize..8, 200u64..1300, 1u64..400), 0..=3),
        proptest::option::of(proptest::collection::vec(5u16..150, 6)),
        proptest::bool::ANY,
    )
        .prop_map(
            |(slaves, cycle_us, words, fibre_m, faults, trts, mdt_after_ats)| {
                let mut ring = StaticRing::new(slaves, cycle_us);
                ring.mdt_after_ats = mdt_after_ats;
                ring.mdt_words = words;
                ring.at_words = words;
                ring.fibre_m = fibre_m;
                ring.at_trt_override = trts;
                let faults = faults
                    .into_iter()
                    .map(|(kind, k, at, len)| any_fault(kind, k, at, len, slaves + 1))
                    .collect();
                (ring, faults)
            },
        )
        .prop_filter("the ring builds", |(ring, _)| ring.build().is_ok())
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64)))]

    // Any small ring with faults: the same run with the slaves running ahead as without
    // (telegram log, counters, every chip after every step).
    #[test]
    fn any_ring_and_faults_run_the_same_with_slaves_ahead(
        (ring, faults) in any_ring_and_faults(),
    ) {
        same_run(&ring, &faults, us(1500), "any ring");
    }
}

// 410B §4.2.1 TRT: ATs set to start on top of one another (and of the MDT) overlap on the
// ring; `early_route` sends ATs on in ring order only when each starts after the one before
// has passed its repeater, so these go at their slaves' wakes. The run is the same with
// the slaves ahead (and past their ATs) as without.
#[test]
fn overlapping_ats_are_sent_at_their_slaves_wakes() {
    for trt in [5u16, 40] {
        let mut ring = StaticRing::new(4, 250);
        ring.mdt_words = 3;
        ring.at_words = 3;
        ring.fibre_m = 1;
        ring.at_trt_override = Some(vec![trt; 6]);
        let (_, quiet) = same_run(&ring, &[], us(1500), "overlapping ATs");
        assert!(quiet.runs_past_output > 0, "{quiet:?}");
        assert_eq!(quiet.ats_sent_on, 0, "{quiet:?}");
    }
}
