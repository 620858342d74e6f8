//! Static phase-4 rings of a master and 1, 8 and 254 slaves (410B §1 Fig. 3, §4.2): the
//! expected telegrams at the expected times, the master's ring delay (11H TCYCDEL), the data
//! exchanged, and the fast path against the reference path.

mod ring_support;

use ring_support::*;
use sercon_model::serial_port::REPEATER_LATENCY_BITS;
use sercon_regs::{Register, SerconBus};
use sercos_sim::static_ring::{StaticRing, at_pattern, mdt_pattern};
use sercos_sim::trace::SegmentId;
use sercos_sim::{Delivery, Fault, FaultKind};
use sercos_wire::line::frame_bit_len;
use sercos_wire::time::{BitRate, Duration, Instant};

/// One MCLK period of the slaves' 32 MHz clock: TRT counts from the first MCLK edge at or
/// after the end of the MST (spec-notes "Telegram processor and MST").
const MCLK_PS: u64 = 31_250;

/// Runs `ring` for `cycles` cycles and checks every telegram's time on the first segment
/// (master → slave 1) and the last one (slave n → master), the data, the headers and
/// TCYCDEL.
fn check_ring(ring: StaticRing, cycles: u64) {
    let n = ring.slaves;
    let bt = ring.bit_rate.bit_time();
    let (cfg, hosts, plan) = build(&ring);
    let cycle = Duration::from_micros(u64::from(ring.cycle_us));
    let (mut sim, out) = run(cfg, hosts, us(0) + cycle.saturating_mul(cycles));
    let lines = parse_log(&out.log);
    let last = n as u16;
    let ring_delay = sim.ring_delay(0, 0, bt).expect("a ring");
    let fibre = Duration::from_nanos(5).saturating_mul(u64::from(ring.fibre_m));
    // 410B §4.1 0CH.10 CYCSTART: one MST per cycle, TSCYC apart.
    let msts: Vec<u64> = lines
        .iter()
        .filter(|l| l.seg == 0 && l.kind == "MST")
        .map(|l| l.ps)
        .collect();
    assert!(msts.len() as u64 >= cycles - 1, "{} MSTs", msts.len());
    for w in msts.windows(2) {
        assert_eq!(w[1] - w[0], cycle.as_picos(), "MST spacing");
    }
    let mst_bits = frame_bit_len(&[255, 4]);
    for &s in msts.iter().take(msts.len() - 1) {
        let mst_end = s + bt.saturating_mul(mst_bits).as_picos();
        // 410B §4.2.1 TRT: the MDT starts TRT µs after the end of the MST.
        let mdt = lines
            .iter()
            .find(|l| l.seg == 0 && l.kind == "MDT" && l.ps > s)
            .expect("an MDT each cycle");
        let want = mst_end + u64::from(plan.mdt_trt_us) * 1_000_000;
        assert!(
            mdt.ps.abs_diff(want) <= bt.as_picos(),
            "MDT at {} want {want}",
            mdt.ps
        );
        assert!(mdt.ok);
        // Each slave's AT: TRT after the MST's end at that slave, then down the ring.
        for i in 1..=n {
            let at = lines
                .iter()
                .find(|l| l.seg == last && l.kind == "AT" && l.adr == Some(i as u8) && l.ps > s)
                .unwrap_or_else(|| panic!("AT {i} after {s}"));
            // The sender does not repeat its own AT: one repeater latency less.
            let want = mst_end + ring_delay.as_picos()
                - bt.saturating_mul(REPEATER_LATENCY_BITS).as_picos()
                + u64::from(plan.at_trt_us[i - 1]) * 1_000_000
                - fibre.as_picos();
            assert!(
                at.ps >= want && at.ps - want <= bt.as_picos().max(MCLK_PS),
                "AT {i} at {} want {want}",
                at.ps
            );
            assert!(at.ok);
        }
    }
    // Nothing else on the last segment: MST, MDT and n ATs per cycle.
    let per_cycle = lines.iter().filter(|l| l.seg == last).count() as f64 / msts.len() as f64;
    assert!(
        per_cycle <= (n + 2) as f64,
        "{per_cycle} telegrams per cycle"
    );
    // 410B §4.1 11H TCYCDEL: the master's measured ring delay, in µs of TCNT.
    let m = sim.chip_mut(0).expect("master");
    let tcycdel = m.read_register(Register::Tcycdel.address());
    let want_us = ring_delay.as_picos() as f64 / 1e6;
    assert!(
        (f64::from(tcycdel) - want_us).abs() <= 1.0,
        "TCYCDEL {tcycdel} µs, ring delay {want_us} µs"
    );
    // 410B §4.2.1: every AT arrived valid at the master, no errors; data as sent.
    for i in 1..=n {
        let h = rx_header(m, plan.master_at_header[i - 1]);
        assert!(h.val && !h.rerr && h.nerr == 0, "master AT {i}: {h:?}");
        if let Some(d) = plan.master_at_data[i - 1] {
            let want: Vec<u16> = (0..ring.at_words).map(|k| at_pattern(i, k)).collect();
            assert_eq!(words(m, d, ring.at_words), want, "AT {i} data");
        }
    }
    // 410B §4.1 17H PROGERR_FL: no header reached after its TRT, no list error.
    assert_eq!(m.read_register(0x17), 0, "master PROGERR_FL");
    for i in 1..=n {
        let s = sim.chip_mut(i).expect("slave");
        assert_eq!(s.read_register(0x17), 0, "slave {i} PROGERR_FL");
        let h = rx_header(s, plan.slave_mdt_header);
        assert!(h.val && !h.rerr && h.nerr == 0, "slave {i} MDT: {h:?}");
        let first = (i as u16 - 1) * ring.mdt_words;
        let want: Vec<u16> = (0..ring.mdt_words)
            .map(|k| {
                if first + k < plan.mdt_container_len {
                    mdt_pattern(i, k)
                } else {
                    0 // 410B §4.2.2: beyond the container the telegram carries 0
                }
            })
            .collect();
        assert_eq!(
            words(s, plan.slave_mdt_data, ring.mdt_words),
            want,
            "slave {i} data"
        );
    }
}

#[test]
fn one_slave_phase4_telegrams_at_trt() {
    check_ring(StaticRing::new(1, 250), 4);
}

#[test]
fn eight_slaves_phase4_telegrams_at_trt_and_ring_delay() {
    let mut ring = StaticRing::new(8, 250);
    // Long fibres: a ring delay of about 10 µs that TCYCDEL must show.
    ring.fibre_m = 200;
    check_ring(ring, 4);
}

#[test]
fn eight_slaves_at_2_mbit() {
    let mut ring = StaticRing::new(8, 1000);
    ring.bit_rate = BitRate::Mbit2;
    ring.mdt_words = 2;
    ring.at_words = 2;
    check_ring(ring, 3);
}

#[test]
fn two_hundred_fifty_four_slaves_phase4() {
    // The master's RAM (816: 2048 words) holds no AT data for 254 slaves: the AT
    // containers have LEN 0 and the MDT container covers what fits.
    let mut ring = StaticRing::new(254, 4000);
    ring.mdt_words = 1;
    ring.at_words = 1;
    check_ring(ring, 3);
}

// 410B §4.2.1 TRT, §4.2: the ATs before the MDT (MST, AT 1 … AT n, MDT; T1 before T2, the
// order the master driver plans): every telegram at its time, data and TCYCDEL as in the
// other order, and on the master's input fibre each cycle in that order.
#[test]
fn eight_slaves_with_the_mdt_after_the_ats() {
    let mut ring = StaticRing::new(8, 250);
    ring.fibre_m = 200;
    ring.mdt_after_ats = true;
    let (_, _, plan) = build(&ring);
    assert!(
        plan.at_trt_us.iter().all(|&t| t < plan.mdt_trt_us),
        "{plan:?}"
    );
    check_ring(ring.clone(), 4);
    let (cfg, hosts, _) = build(&ring);
    let (_, out) = run(cfg, hosts, us(1000));
    let kinds: Vec<(String, Option<u8>)> = parse_log(&out.log)
        .into_iter()
        .filter(|l| l.seg == 8)
        .map(|l| (l.kind.to_string(), l.adr))
        .collect();
    let mut want = vec![("MST".to_string(), Some(255))];
    want.extend((1..=8).map(|i| ("AT".to_string(), Some(i))));
    want.push(("MDT".to_string(), Some(255)));
    // The telegrams of each cycle, from one MST to the next; the first cycle (the slaves
    // not yet synchronised) and the last (cut by the run's end) left out.
    let mut cycles: Vec<Vec<(String, Option<u8>)>> = Vec::new();
    for t in kinds {
        if t.0 == "MST" {
            cycles.push(Vec::new());
        }
        if let Some(c) = cycles.last_mut() {
            c.push(t);
        }
    }
    let steady = cycles.get(1..cycles.len().saturating_sub(1)).unwrap_or(&[]);
    assert!(steady.len() >= 2, "{} cycles", steady.len());
    for c in steady {
        assert_eq!(c, &want);
    }
}

// 410B §4.2 (the master walks its list in order: the AT headers, then the MDT's) and
// §4.2.1 TRT: on a long ring the last AT reaches the master a ring delay after its TRT at
// the slave, so the MDT's TRT lies after that; the MDT starts at its time and no header is
// reached late (before, on rings of about 90 slaves and more, the master's MDT header was reached after
// its TRT every cycle: 17H PROGERR_FL, the MDT late).
#[test]
fn a_long_ring_with_the_mdt_after_the_ats_sends_its_mdt_at_its_time() {
    let mut ring = StaticRing::new(128, 4000);
    // 410B §4.2.2: at most 1023 words in the MDT's container.
    ring.mdt_words = 4;
    ring.mdt_after_ats = true;
    let (_, _, plan) = build(&ring);
    // Ring delay: 129 fibres of 10 m and 128 repeaters of two bit times (≈ 22.5 µs).
    let ring_ps = Duration::from_nanos(50).as_picos() * 129
        + ring.bit_rate.bit_time().saturating_mul(256).as_picos();
    let last_at = plan.at_trt_us.iter().copied().max().unwrap_or(0);
    assert!(
        u64::from(plan.mdt_trt_us - last_at) * 1_000_000 > ring_ps,
        "{plan:?}"
    );
    check_ring(ring, 3);
}

#[test]
fn the_mdt_after_the_ats_gives_the_exact_path_s_chips_and_trace() {
    let mut ring = compared_ring(6, Delivery::Fast);
    ring.mdt_after_ats = true;
    let (states, events) = exact_and_fast_states(&ring, us(1100));
    assert_eq!(first_difference(&states), None);
    assert!(events[1] * 2 < events[0], "{events:?}");
    let mut logs = Vec::new();
    for delivery in [Delivery::Exact, Delivery::Fast] {
        ring.delivery = delivery;
        let (cfg, hosts, _) = build(&ring);
        let (_, out) = run(cfg, hosts, us(1000));
        logs.push(out.log);
    }
    assert!(parse_log(&logs[0]).len() > 40);
    assert_eq!(
        String::from_utf8_lossy(&logs[0]),
        String::from_utf8_lossy(&logs[1])
    );
}

#[test]
fn fast_path_gives_the_same_trace_as_the_exact_path() {
    // The fast path (no event per repeater, slaves not given other slaves' ATs) against
    // the reference (every repeater's output taken from its chip), on a small ring.
    let mut logs = Vec::new();
    for delivery in [Delivery::Exact, Delivery::Fast] {
        let mut ring = StaticRing::new(3, 250);
        ring.delivery = delivery;
        ring.fibre_m = 30;
        let (cfg, hosts, _) = build(&ring);
        let (sim, out) = run(cfg, hosts, us(1000));
        assert_eq!(sim.stats().out_of_order, 0);
        logs.push(out.log);
    }
    assert!(parse_log(&logs[0]).len() > 40);
    assert_eq!(
        String::from_utf8_lossy(&logs[0]),
        String::from_utf8_lossy(&logs[1])
    );
}

/// The ring the fast and exact paths are compared on: `slaves` slaves at 250 µs, 30 m
/// fibres, two data words each way.
fn compared_ring(slaves: usize, delivery: Delivery) -> StaticRing {
    let mut ring = StaticRing::new(slaves, 250);
    ring.delivery = delivery;
    ring.fibre_m = 30;
    ring.at_words = 2;
    ring.mdt_words = 2;
    ring
}

/// Fast against exact on a ring of `slaves` with the log on the master's input fibre only
/// (so that the fibres between slaves are plain and slave telegrams pass them by sums of
/// delays, 410B §1 "The slaves regenerate and repeat their received data"), with `faults`.
fn fast_equals_exact_at_master_input(slaves: usize, faults: Vec<Fault>, until: Instant) {
    let mut logs = Vec::new();
    for delivery in [Delivery::Exact, Delivery::Fast] {
        let (mut cfg, hosts, _) = build(&compared_ring(slaves, delivery));
        cfg.traces.log_segment = Some(SegmentId(slaves as u16));
        cfg.faults = faults.clone();
        let (_, out) = run(cfg, hosts, until);
        logs.push(out.log);
    }
    assert!(parse_log(&logs[0]).len() > 4 * slaves);
    assert_eq!(
        String::from_utf8_lossy(&logs[0]),
        String::from_utf8_lossy(&logs[1])
    );
}

#[test]
fn fast_path_through_plain_repeaters_gives_the_exact_trace() {
    fast_equals_exact_at_master_input(12, Vec::new(), us(1000));
}

#[test]
fn fast_path_through_plain_repeaters_gives_the_exact_trace_with_faults() {
    // A burst and bit errors on fibres between slaves (not plain: taken hop by hop), a
    // slave whose clock drifts (not plain from then on), a slave switched off and on again.
    let faults = vec![
        Fault {
            at: us(310),
            kind: FaultKind::BitErrorBurst {
                segment: 3,
                bits: 40,
            },
        },
        Fault {
            at: us(520),
            kind: FaultKind::BitErrors {
                segment: 6,
                until: us(700),
                rate: 0.001,
            },
        },
        Fault {
            at: us(400),
            kind: FaultKind::ClockDrift { node: 9, ppm: 80.0 },
        },
        Fault {
            at: us(800),
            kind: FaultKind::PowerOff {
                node: 4,
                until: Some(us(950)),
            },
        },
    ];
    fast_equals_exact_at_master_input(12, faults, us(1250));
}

/// The fast path does not wake a repeating slave for the forwarded copies it carried down
/// the ring itself (410B §1: "The slaves regenerate and repeat their received data";
/// `Chip::next_line_output_except`): the logs on the master's input and on slave 1's input
/// fibre stay those of the exact path, and no segment reaches a chip that has already
/// passed its start more often than on the exact path (a slave woken too late for its own
/// AT would hand it over late).
#[test]
fn unwoken_forwarded_copies_keep_the_exact_trace_and_nothing_late() {
    let slaves = 12;
    for segment in [slaves, 0] {
        let mut runs = Vec::new();
        for delivery in [Delivery::Exact, Delivery::Fast] {
            let (mut cfg, hosts, _) = build(&compared_ring(slaves, delivery));
            cfg.traces.log_segment = Some(SegmentId(segment as u16));
            let (sim, out) = run(cfg, hosts, us(1000));
            runs.push((out.log, sim.stats()));
        }
        let (exact, exact_stats) = &runs[0];
        let (fast, stats) = &runs[1];
        assert!(parse_log(exact).len() > 4);
        assert_eq!(
            String::from_utf8_lossy(exact),
            String::from_utf8_lossy(fast)
        );
        // The exact path takes every forwarded copy from its chip; the fast path must not
        // hand any segment over later than it does.
        assert!(stats.late <= exact_stats.late, "{stats:?} {exact_stats:?}");
        assert_eq!(stats.out_of_order, 0, "{stats:?}");
    }
}

/// Every chip's RAM and registers after running `ring` to `until` the exact way and the fast
/// way (a slave's 3H.15 REACTN left out: the fast path gives slaves no other slave's AT,
/// spec-notes "Fast path = reference path"), and the events of each run.
fn exact_and_fast_states(ring: &StaticRing, until: Instant) -> ([ChipStates; 2], [u64; 2]) {
    let mut states: [ChipStates; 2] = Default::default();
    let mut events = [0; 2];
    for (k, delivery) in [Delivery::Exact, Delivery::Fast].into_iter().enumerate() {
        let mut ring = ring.clone();
        ring.delivery = delivery;
        let (cfg, hosts, _) = build(&ring);
        let (mut sim, _) = run(cfg, hosts, until);
        events[k] = sim.stats().events;
        for i in 0..=ring.slaves {
            let chip = sim.chip_mut(i).expect("node");
            let ram: Vec<u16> = (0..2048).map(|a| chip.read_ram(a)).collect();
            let mut regs: Vec<u16> = (0..0x40u8).map(|a| chip.read_register(a)).collect();
            if i > 0 {
                regs[3] &= !(1 << 15);
            }
            states[k].push((ram, regs));
        }
    }
    (states, events)
}

/// RAM and registers of each node.
type ChipStates = Vec<(Vec<u16>, Vec<u16>)>;

/// The first node whose state differs, with the words that differ as (address, exact,
/// fast).
fn first_difference(states: &[ChipStates; 2]) -> Option<String> {
    let differ = |a: &[u16], b: &[u16]| -> Vec<(usize, u16, u16)> {
        a.iter()
            .zip(b)
            .enumerate()
            .filter(|(_, (x, y))| x != y)
            .map(|(k, (x, y))| (k, *x, *y))
            .collect()
    };
    states[0]
        .iter()
        .zip(&states[1])
        .enumerate()
        .find_map(|(i, (a, b))| {
            let (ram, regs) = (differ(&a.0, &b.0), differ(&a.1, &b.1));
            (!ram.is_empty() || !regs.is_empty())
                .then(|| format!("node {i}: RAM {ram:x?} registers {regs:x?}"))
        })
}

/// The fast path lets a chip sleep until its next possible own telegram
/// (`Chip::next_output_bound`, 410B §4.2.1 TRT) and processes its receive telegrams at the
/// next advance: at the end of the run every chip holds what the exact path's chips hold
/// (RAM: received data, VAL, NERR, NMSTERR, TEND; registers: status, counters, flags), with
/// far fewer events.
#[test]
fn sleeping_through_receive_events_leaves_every_chip_as_the_exact_path() {
    let (states, events) = exact_and_fast_states(&compared_ring(12, Delivery::Fast), us(1100));
    assert_eq!(first_difference(&states), None);
    assert!(
        events[1] * 2 < events[0],
        "fast {} events, exact {}",
        events[1],
        events[0]
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(12)))]

    // The same for any small ring: bit rate, cycle, data words, fibre length, and a run that
    // ends anywhere in a cycle (chips asleep in the middle of their receive events).
    #[test]
    fn any_ring_leaves_every_chip_as_the_exact_path(
        slaves in 1usize..=5,
        rate in 0usize..4,
        cycle_us in 250u16..=1000,
        mdt_words in 1u16..=4,
        at_words in 1u16..=4,
        fibre_m in 1u32..=300,
        end_us in 1500u64..=3000,
        mdt_after_ats: bool,
    ) {
        let mut ring = StaticRing::new(slaves, cycle_us);
        ring.mdt_after_ats = mdt_after_ats;
        ring.bit_rate = [BitRate::Mbit2, BitRate::Mbit4, BitRate::Mbit8, BitRate::Mbit16][rate];
        ring.mdt_words = mdt_words;
        ring.at_words = at_words;
        ring.fibre_m = fibre_m;
        proptest::prop_assume!(ring.build().is_ok());
        let (states, _) = exact_and_fast_states(&ring, us(end_us));
        proptest::prop_assert_eq!(first_difference(&states), None);
    }
}

#[test]
fn rings_that_do_not_fit_are_refused_not_panicking() {
    for (slaves, cycle, words) in [(0, 250, 8), (255, 4000, 1), (8, 50, 8), (1, 65535, 1024)] {
        let mut ring = StaticRing::new(slaves, cycle);
        ring.mdt_words = words;
        ring.at_words = words;
        assert!(ring.build().is_err(), "{slaves} {cycle} {words}");
    }
}

// 410B §1 (repeaters), §4.2.1 TRT: on 2 km fibres slave 2's AT starts 5 µs after the master
// has started its MDT, 25 µs before the MDT reaches slave 2, and passes slave 3 ahead of it;
// slave 3's AT comes after the MDT. Fast path and reference give the same trace, logged on
// every fibre and on the master's input only (plain repeaters between the slaves).
#[test]
fn an_at_after_the_master_s_next_telegram_started_gives_the_exact_trace() {
    for master_input_only in [false, true] {
        let mut logs = Vec::new();
        for delivery in [Delivery::Exact, Delivery::Fast] {
            let mut ring = StaticRing::new(3, 500);
            ring.fibre_m = 2000;
            ring.mdt_words = 1;
            ring.at_words = 1;
            ring.mdt_after_ats = true;
            ring.delivery = delivery;
            let (_, _, plan) = build(&ring);
            let mut trts = plan.at_trt_us.clone();
            trts[1] = plan.mdt_trt_us - 15;
            trts[2] = plan.mdt_trt_us + 60;
            ring.at_trt_override = Some(trts);
            let (mut cfg, hosts, _) = build(&ring);
            if master_input_only {
                cfg.traces.log_segment = Some(SegmentId(3));
            }
            let (sim, out) = run(cfg, hosts, us(3000));
            assert_eq!(sim.stats().out_of_order, 0);
            logs.push(out.log);
        }
        assert!(
            parse_log(&logs[0])
                .iter()
                .filter(|l| l.kind == "AT")
                .count()
                >= 3 * 4
        );
        assert_eq!(
            String::from_utf8_lossy(&logs[0]),
            String::from_utf8_lossy(&logs[1]),
            "logged on the master's input only: {master_input_only}"
        );
    }
}
