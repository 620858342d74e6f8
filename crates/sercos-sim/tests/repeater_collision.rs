//! Telegrams that meet at a repeater's output (410B §1: "The slaves regenerate and repeat
//! their received data or send their own telegrams"; spec-notes "Repeater collisions"): the
//! reference path gives the chips' reading (the own telegram cuts or shadows the repeated
//! one), and the fast path reports every run it cannot follow
//! (`SimStats::fast_path_collisions`).

mod ring_support;

use ring_support::*;
use sercon_model::serial_port::REPEATER_LATENCY_BITS;
use sercos_sim::static_ring::StaticRing;
use sercos_sim::{Delivery, SimStats};
use sercos_wire::time::{Duration, Instant};

/// One MCLK period of the 32 MHz chips: TRT counts from the first MCLK edge at or after the
/// end of the MST (spec-notes "Telegram processor and MST").
const MCLK_PS: u64 = 31_250;

/// Two slaves, slave 2's AT TRT `shift` µs after slave 1's (410B §4.2.1 TRT), run for
/// `cycles` 250 µs cycles on `delivery`: the log's lines, the statistics, the master's
/// receive headers of AT 1 and AT 2.
fn two_slaves(shift: i32, cycles: u64, delivery: Delivery) -> (Vec<Line>, SimStats, [RxState; 2]) {
    let mut ring = StaticRing::new(2, 250);
    ring.delivery = delivery;
    let (_, _, plan) = build(&ring);
    let trt1 = plan.at_trt_us[0];
    let trt2 = u16::try_from(i32::from(trt1) + shift).expect("a TRT");
    ring.at_trt_override = Some(vec![trt1, trt2]);
    let (cfg, hosts, plan) = build(&ring);
    let (mut sim, out) = run(cfg, hosts, us(250 * cycles));
    let stats = sim.stats();
    let m = sim.chip_mut(0).expect("master");
    let ats = [0, 1].map(|i| {
        let h = rx_header(m, plan.master_at_header[i]);
        RxState {
            val: h.val,
            rerr: h.rerr,
            nerr: h.nerr,
        }
    });
    (parse_log(&out.log), stats, ats)
}

/// What the master's receive header of an AT says (410B §4.2.1).
#[derive(Debug, Clone, Copy)]
struct RxState {
    val: bool,
    rerr: bool,
    nerr: u16,
}

/// The start of AT `adr` on segment `seg` in each cycle after the first (ps).
fn at_times(lines: &[Line], seg: u16, adr: u8, ok: bool) -> Vec<u64> {
    lines
        .iter()
        .filter(|l| l.seg == seg && l.kind == "AT" && l.adr == Some(adr) && l.ok == ok)
        .filter(|l| l.ps > 250_000_000)
        .map(|l| l.ps)
        .collect()
}

/// Fibre delay of the default 10 m fibres plus the repeater latency at 16 Mbit/s: how much
/// later the MST ends at slave 2 than at slave 1 (410B §1).
fn hop() -> u64 {
    let bt = sercos_wire::time::BitRate::Mbit16.bit_time();
    Duration::from_nanos(50).as_picos() + bt.saturating_mul(REPEATER_LATENCY_BITS).as_picos()
}

// 410B §1, §4.2.1 TRT: slave 2's AT starts 1 µs after slave 1's AT reached its output, in
// the middle of it. The chip sends its own telegram at its TRT and the repeated one is cut
// there: on the fibre to the master slave 2's AT starts at its time (before, the simulator
// held it behind slave 1's, 13 µs late and intact both); slave 1's AT never reaches the
// master whole (it leaves slave 1 whole).
#[test]
fn an_own_telegram_cuts_the_one_its_repeater_is_sending() {
    let cycles = 6;
    let (lines, stats, [at1, at2]) = two_slaves(1, cycles, Delivery::Exact);
    let sent = at_times(&lines, 1, 1, true);
    let own = at_times(&lines, 2, 2, true);
    assert_eq!(
        sent.len() as u64,
        cycles - 1,
        "AT 1 leaves slave 1 whole each cycle"
    );
    assert_eq!(own.len(), sent.len(), "AT 2 each cycle");
    for (t1, t2) in sent.iter().zip(&own) {
        let want = t1 + hop() + 1_000_000;
        assert!(
            t2.abs_diff(want) <= MCLK_PS,
            "AT 2 at {t2}, want {want} (AT 1 at {t1})"
        );
    }
    assert!(
        at_times(&lines, 2, 1, true).is_empty(),
        "AT 1 whole on the fibre to the master"
    );
    assert!(
        at2.val && !at2.rerr && at2.nerr == 0,
        "master's AT 2: {at2:?}"
    );
    assert!(at1.nerr > 0 || at1.rerr, "master's AT 1: {at1:?}");
    assert_eq!(
        stats.fast_path_collisions, 0,
        "counted on the fast path only"
    );
    // The fast path cannot follow it and says so.
    let (_, fast, _) = two_slaves(1, cycles, Delivery::Fast);
    assert!(fast.fast_path_collisions > 0, "{fast:?}");
}

// 410B §1: slave 2's AT starts 1 µs before slave 1's reaches its output; the repeated AT
// comes in while the chip sends its own, which shadows it: after its end only the rest of
// slave 1's AT goes on (no telegram). Slave 2's AT is whole and at its time.
#[test]
fn an_own_telegram_shadows_a_telegram_reaching_its_repeater_during_it() {
    let cycles = 6;
    let (lines, _, [at1, at2]) = two_slaves(-1, cycles, Delivery::Exact);
    let sent = at_times(&lines, 1, 1, true);
    let own = at_times(&lines, 2, 2, true);
    assert_eq!(own.len(), sent.len());
    for (t1, t2) in sent.iter().zip(&own) {
        let want = t1 + hop() - 1_000_000;
        assert!(t2.abs_diff(want) <= MCLK_PS, "AT 2 at {t2}, want {want}");
    }
    assert!(at_times(&lines, 2, 1, true).is_empty());
    assert!(at2.val && !at2.rerr && at2.nerr == 0, "{at2:?}");
    assert!(at1.nerr > 0 || at1.rerr, "{at1:?}");
    let (_, fast, _) = two_slaves(-1, cycles, Delivery::Fast);
    assert!(fast.fast_path_collisions > 0, "{fast:?}");
}

// Clear of each other by 20 µs: no collision, the fast path counts none and gives the
// reference path's log.
#[test]
fn telegrams_clear_of_each_other_are_no_collision() {
    let (exact, _, _) = two_slaves(20, 6, Delivery::Exact);
    let (fast, stats, [at1, at2]) = two_slaves(20, 6, Delivery::Fast);
    assert_eq!(stats.fast_path_collisions, 0);
    assert_eq!(exact, fast);
    assert!(at1.val && at1.nerr == 0 && at2.val && at2.nerr == 0);
}

/// Every node's registers then RAM (3H.15 REACTN of slaves left out).
type States = Vec<Vec<u16>>;

/// Runs `base` on the reference path and the fast path to `end`: their logs, the fast
/// path's collisions, and their chips' states.
fn both_paths(base: &StaticRing, end: Instant) -> ([Vec<u8>; 2], u64, [States; 2]) {
    let mut logs: [Vec<u8>; 2] = Default::default();
    let mut states: [States; 2] = Default::default();
    let mut collisions = 0;
    for (k, delivery) in [Delivery::Exact, Delivery::Fast].into_iter().enumerate() {
        let mut ring = base.clone();
        ring.delivery = delivery;
        let (cfg, hosts, _) = build(&ring);
        let (mut sim, out) = run(cfg, hosts, end);
        if delivery == Delivery::Fast {
            collisions = sim.stats().fast_path_collisions;
        }
        logs[k] = out.log;
        states[k] = node_states(&mut sim, ring.slaves);
    }
    (logs, collisions, states)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(
        std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(16)
    ))]

    // Any AT layout, colliding or not (410B §4.2.1 TRT, §1 repeaters): a fast run that
    // reports no collision gives the reference path's log and leaves every chip as it does;
    // the reference path itself counts none.
    #[test]
    fn the_fast_path_reports_every_run_it_cannot_follow(
        slaves in 2usize..=5,
        cycle_us in 250u16..=600,
        words in 1u16..=4,
        fibre_m in 1u32..=300,
        shifts in proptest::collection::vec(-30i32..=30, 5),
        end_us in 1500u64..=2500,
        mdt_after_ats: bool,
    ) {
        let mut base = StaticRing::new(slaves, cycle_us);
        base.mdt_after_ats = mdt_after_ats;
        base.mdt_words = words;
        base.at_words = words;
        base.fibre_m = fibre_m;
        proptest::prop_assume!(base.build().is_ok());
        let (_, _, plan) = build(&base);
        let trts: Vec<u16> = plan
            .at_trt_us
            .iter()
            .zip(&shifts)
            .map(|(t, s)| (i32::from(*t) + s).clamp(1, i32::from(cycle_us) - 1))
            .map(|t| u16::try_from(t).unwrap_or(1))
            .collect();
        base.at_trt_override = Some(trts);
        let (logs, collisions, states) = both_paths(&base, us(end_us));
        if collisions == 0 {
            proptest::prop_assert_eq!(
                String::from_utf8_lossy(&logs[0]),
                String::from_utf8_lossy(&logs[1])
            );
            for (i, (a, b)) in states[0].iter().zip(&states[1]).enumerate() {
                let d: Vec<_> = a
                    .iter()
                    .zip(b)
                    .enumerate()
                    .filter(|(_, (x, y))| x != y)
                    .take(8)
                    .collect();
                proptest::prop_assert!(d.is_empty(), "node {} differs: {:x?}", i, d);
            }
        }
    }
}

// Found by the property test above (debug builds panicked on both paths before): slave 5's
// AT shadows slave 4's at its output, whose rest follows it; the master's receiver decodes
// that rest's end only once it sees the next telegram come in, an event earlier than the
// wake the simulation had kept for it. The wake found is taken (`Simulation::deliver`), and
// the run goes on on both paths.
#[test]
fn a_rest_decoded_late_wakes_the_master_in_time() {
    let mut base = StaticRing::new(5, 250);
    base.mdt_words = 1;
    base.at_words = 1;
    base.fibre_m = 75;
    let (_, _, plan) = build(&base);
    let trts: Vec<u16> = plan
        .at_trt_us
        .iter()
        .zip([0, 20, 12, 0, -1])
        .map(|(t, s)| u16::try_from(i32::from(*t) + s).expect("a TRT"))
        .collect();
    base.at_trt_override = Some(trts);
    let (logs, collisions, _) = both_paths(&base, us(1500));
    assert!(collisions > 0);
    let exact = parse_log(&logs[0]);
    for adr in 1..=5 {
        assert!(
            exact.iter().any(|l| l.kind == "AT" && l.adr == Some(adr)),
            "AT {adr} on the reference path"
        );
    }
}

// Found by the property test above: the fast path knows arrivals ahead of time and wrote the
// MST's records on the fibres after the first although the run ended before it reached them
// (the reference path had not sent it on yet). A trace holds what the line carried up to
// the run's end, on both paths.
#[test]
fn a_trace_ends_where_the_run_ends() {
    let mut ring = StaticRing::new(2, 454);
    ring.mdt_words = 1;
    ring.at_words = 1;
    ring.fibre_m = 235;
    let end = us(2274);
    let (logs, collisions, _) = both_paths(&ring, end);
    assert_eq!(collisions, 0);
    assert_eq!(
        String::from_utf8_lossy(&logs[0]),
        String::from_utf8_lossy(&logs[1])
    );
    let lines = parse_log(&logs[1]);
    assert!(lines.iter().all(|l| l.ps <= end.as_picos()));
    // The MST sent at 2273.4 µs is on the first fibre, not yet on the second.
    assert!(
        lines
            .iter()
            .any(|l| l.seg == 0 && l.kind == "MST" && l.ps > 2_273_000_000)
    );
    assert!(
        !lines
            .iter()
            .any(|l| l.seg == 1 && l.kind == "MST" && l.ps > 2_273_000_000)
    );
}
