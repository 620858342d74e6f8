//! Faults on a static phase-4 ring and what the controllers report (410B §4.1 2H.12 RDIST,
//! 2H.13 FIBBR, 4H.0/4H.1/4H.9 interrupts, §4.2 NMSTERR, §4.2.1 RERR/NERR/VAL): fibre break
//! and repair, bit-error bursts and random bit errors, power off and on, clock drift,
//! distortion, and collisions on the RS-485 bus (410B §1 Fig. 4).

mod ring_support;

use ring_support::*;
use sercon_model::serial_port::REPEATER_LATENCY_BITS;
use sercon_regs::{Register, SerconBus};
use sercos_sim::sim::Simulation;
use sercos_sim::static_ring::{RingPlan, StaticRing, at_pattern, mdt_pattern};
use sercos_sim::trace::SegmentId;
use sercos_sim::{Delivery, Fault, FaultKind, Topology};
use sercos_wire::line::frame_bit_len;
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 4H.0 INT_RDIST, 4H.1 INT_FIBBR, 4H.9 INT_MSTMIS.
const INT_RDIST: u16 = 1 << 0;
const INT_FIBBR: u16 = 1 << 1;
const INT_MSTMIS: u16 = 1 << 9;
/// 410B §4.1 2H.12 RDIST, 2H.13 FIBBR.
const RDIST: u16 = 1 << 12;
const FIBBR: u16 = 1 << 13;
/// 410B §4.2: RAM word 10, NMSTERR.
const NMSTERR: u16 = 10;

fn sim_with(ring: &StaticRing, faults: Vec<Fault>) -> (Simulation, RingPlan) {
    let (mut cfg, hosts, plan) = build(ring);
    cfg.faults = faults;
    (Simulation::new(cfg, hosts).expect("valid"), plan)
}

/// Clears every interrupt flag of every node (410B §4.1 4H/5H: write 1 to clear).
fn clear_ints(sim: &mut Simulation) {
    for i in 0..sim.node_count() {
        let c = sim.chip_mut(i).expect("node");
        c.write_register(Register::IntFlagsLo.address(), 0xFFFF);
        c.write_register(Register::IntFlagsHi.address(), 0xFFFF);
    }
}

fn reg(sim: &mut Simulation, node: usize, r: Register) -> u16 {
    sim.chip_mut(node).expect("node").read_register(r.address())
}

fn nerr_master(sim: &mut Simulation, plan: &RingPlan, slave: usize) -> (u16, bool, bool) {
    let h = rx_header(
        sim.chip_mut(0).expect("master"),
        plan.master_at_header[slave - 1],
    );
    (h.nerr, h.rerr, h.val)
}

fn nerr_slave(sim: &mut Simulation, plan: &RingPlan, slave: usize) -> u16 {
    rx_header(sim.chip_mut(slave).expect("slave"), plan.slave_mdt_header).nerr
}

#[test]
fn fibre_break_sets_fibbr_downstream_and_the_ring_recovers_after_repair() {
    let ring = StaticRing::new(4, 250);
    // Segment 2 runs from slave 2 to slave 3.
    let (mut sim, plan) = sim_with(
        &ring,
        vec![Fault {
            at: us(1000),
            kind: FaultKind::FibreBreak {
                segment: 2,
                until: Some(us(2000)),
            },
        }],
    );
    sim.run_until(us(900)).expect("runs");
    clear_ints(&mut sim);
    sim.run_until(us(1990)).expect("runs");
    // 410B §4.1 2H.13 FIBBR "No edges on receive data" and 4H.1 INT_FIBBR: at slave 3 (the
    // broken fibre's end), at slave 4 and the master (dark repeated), not upstream.
    for node in [3, 4, 0] {
        assert!(
            reg(&mut sim, node, Register::Ctrl2) & FIBBR != 0,
            "FIBBR at {node}"
        );
        assert!(
            reg(&mut sim, node, Register::IntFlagsLo) & INT_FIBBR != 0,
            "INT at {node}"
        );
    }
    for node in [1, 2] {
        assert_eq!(
            reg(&mut sim, node, Register::Ctrl2) & FIBBR,
            0,
            "FIBBR at {node}"
        );
        assert_eq!(reg(&mut sim, node, Register::IntFlagsLo) & INT_FIBBR, 0);
    }
    // 410B §4.2 NMSTERR and 4H.9 INT_MSTMIS: slaves behind the break miss the MST.
    for node in [3, 4] {
        let c = sim.chip_mut(node).expect("slave");
        assert!(c.read_ram(NMSTERR) >= 2, "NMSTERR at {node}");
        assert!(c.read_register(Register::IntFlagsLo.address()) & INT_MSTMIS != 0);
    }
    // Every AT is missing at the master (the ring is open): RERR, NERR counted.
    for s in 1..=4 {
        let (nerr, rerr, _) = nerr_master(&mut sim, &plan, s);
        assert!(rerr && nerr >= 3, "AT {s}: nerr {nerr}");
    }
    // After the repair the light is back and the exchange runs without new errors.
    sim.run_until(us(2600)).expect("runs");
    let before: Vec<u16> = (1..=4).map(|s| nerr_master(&mut sim, &plan, s).0).collect();
    // Late in a cycle, after the last AT (VAL is 0 while an AT is being received).
    sim.run_until(us(3700)).expect("runs");
    for s in 1..=4 {
        let (nerr, rerr, val) = nerr_master(&mut sim, &plan, s);
        assert_eq!(nerr, before[s - 1], "AT {s} errors after repair");
        assert!(
            !rerr && val,
            "AT {s}: {:?}",
            nerr_master(&mut sim, &plan, s)
        );
    }
    assert_eq!(reg(&mut sim, 3, Register::Ctrl2) & FIBBR, 0);
}

#[test]
fn bit_error_bursts_count_nerr_once_per_corrupted_telegram_and_store_nothing() {
    let ring = StaticRing::new(3, 250);
    let (cfg, _, plan) = build(&ring);
    let _ = cfg;
    // MDT bursts on segment 0 in cycles 2, 4, 5 (the cycle starts when the master's host
    // has written its image, ~8.5 µs; the MST takes 3 µs, the MDT follows 4 µs later), AT-2 bursts on segment 3 (slave 3 → master) in cycles 3 and 6.
    let mut faults = Vec::new();
    for c in [2u64, 4, 5] {
        faults.push(Fault {
            at: us(c * 250 + 13),
            kind: FaultKind::BitErrorBurst {
                segment: 0,
                bits: 4,
            },
        });
    }
    for c in [3u64, 6] {
        faults.push(Fault {
            at: us(c * 250 + 6 + u64::from(plan.at_trt_us[1])),
            kind: FaultKind::BitErrorBurst {
                segment: 3,
                bits: 3,
            },
        });
    }
    let (mut cfg, hosts, plan) = build(&ring);
    cfg.faults = faults;
    let (mut sim, out) = run(cfg, hosts, us(2000));
    let lines = parse_log(&out.log);
    // The log shows frames in error (a burst may split one frame into two broken ones)
    // exactly in the cycles hit.
    let cycles_hit = |seg: u16, master: bool| {
        let mut c: Vec<u64> = lines
            .iter()
            .filter(|l| l.seg == seg && !l.ok && l.master == master)
            .map(|l| l.ps / 250_000_000)
            .collect();
        c.dedup();
        c
    };
    let bad: Vec<_> = lines.iter().filter(|l| !l.ok).collect();
    assert_eq!(cycles_hit(0, true), vec![2, 4, 5], "{bad:?}");
    // The corrupted MDTs come back to the master on segment 3 too; the ATs hit are 2.
    assert_eq!(cycles_hit(3, false), vec![3, 6]);
    // 410B §4.2.1 NERR: one count per errored receive telegram, at every slave (the MDT
    // is corrupted before slave 1 and repeated as it is); no data stored from them.
    for s in 1..=3 {
        assert_eq!(nerr_slave(&mut sim, &plan, s), 3, "slave {s}");
        let want: Vec<u16> = (0..ring.mdt_words).map(|k| mdt_pattern(s, k)).collect();
        let c = sim.chip_mut(s).expect("slave");
        assert_eq!(words(c, plan.slave_mdt_data, ring.mdt_words), want);
    }
    assert_eq!(nerr_master(&mut sim, &plan, 1).0, 0);
    assert_eq!(nerr_master(&mut sim, &plan, 2).0, 2);
    assert_eq!(nerr_master(&mut sim, &plan, 3).0, 0);
    let m = sim.chip_mut(0).expect("master");
    let d = plan.master_at_data[1].expect("stored");
    let want: Vec<u16> = (0..ring.at_words).map(|k| at_pattern(2, k)).collect();
    assert_eq!(words(m, d, ring.at_words), want);
}

/// A ring with random bit errors on segment 1 (slave 1 → slave 2) for 2 ms.
fn noisy(seed: u64) -> (Simulation, sercos_sim::recorder::TraceOutput, RingPlan) {
    let mut ring = StaticRing::new(3, 250);
    ring.seed = seed;
    let (mut cfg, hosts, plan) = build(&ring);
    cfg.traces.hash = true;
    cfg.traces.log_segment = Some(SegmentId(1));
    cfg.faults = vec![Fault {
        at: us(500),
        kind: FaultKind::BitErrors {
            segment: 1,
            until: us(2500),
            rate: 1e-3,
        },
    }];
    let (sim, out) = run(cfg, hosts, us(3000));
    (sim, out, plan)
}

#[test]
fn random_bit_errors_are_seeded_and_counted_downstream_only() {
    let (mut sim, out, plan) = noisy(7);
    let lines = parse_log(&out.log);
    let bad_mdt = lines.iter().filter(|l| !l.ok && l.master).count() as u16;
    assert!(bad_mdt > 0, "some MDT or MST must be hit at this rate");
    // Upstream of the noisy fibre nothing happens; downstream both slaves see the same
    // corrupted MDTs (410B §4.2.1 NERR), and at least every frame the log shows in error.
    assert_eq!(nerr_slave(&mut sim, &plan, 1), 0);
    let n2 = nerr_slave(&mut sim, &plan, 2);
    let n3 = nerr_slave(&mut sim, &plan, 3);
    assert_eq!(n2, n3);
    assert!(n2 > 0 && n2 <= 12, "NERR {n2}");
    for s in 2..=3 {
        let want: Vec<u16> = (0..8).map(|k| mdt_pattern(s, k)).collect();
        let c = sim.chip_mut(s).expect("slave");
        assert_eq!(
            words(c, plan.slave_mdt_data, 8),
            want,
            "no corrupted data stored"
        );
    }
    // The same seed gives the same trace, byte for byte; another seed another one.
    let (_, again, _) = noisy(7);
    assert_eq!(out.hash, again.hash);
    assert_eq!(out.log, again.log);
    let (_, other, _) = noisy(8);
    assert_ne!(out.hash, other.hash);
}

#[test]
fn power_off_and_on_of_a_slave() {
    let ring = StaticRing::new(4, 250);
    let (mut sim, plan) = sim_with(
        &ring,
        vec![Fault {
            at: us(1000),
            kind: FaultKind::PowerOff {
                node: 2,
                until: Some(us(2000)),
            },
        }],
    );
    sim.run_until(us(900)).expect("runs");
    clear_ints(&mut sim);
    sim.run_until(us(1990)).expect("runs");
    assert!(!sim.powered(2));
    // The dark output of slave 2 reaches slave 3 (FIBBR, MST missing) and the master.
    assert!(reg(&mut sim, 3, Register::Ctrl2) & FIBBR != 0);
    assert!(sim.chip_mut(3).expect("slave").read_ram(NMSTERR) >= 2);
    assert_eq!(reg(&mut sim, 1, Register::Ctrl2) & FIBBR, 0);
    for s in 1..=4 {
        assert!(nerr_master(&mut sim, &plan, s).1, "AT {s} missing");
    }
    // Powered again, its host writes the image anew and the ring runs as before.
    sim.run_until(us(2800)).expect("runs");
    assert!(sim.powered(2));
    let before: Vec<u16> = (1..=4).map(|s| nerr_master(&mut sim, &plan, s).0).collect();
    sim.run_until(us(3700)).expect("runs");
    for s in 1..=4 {
        let (nerr, rerr, val) = nerr_master(&mut sim, &plan, s);
        assert_eq!(nerr, before[s - 1], "AT {s}");
        assert!(!rerr && val);
    }
    let want: Vec<u16> = (0..8).map(|k| mdt_pattern(2, k)).collect();
    let c = sim.chip_mut(2).expect("slave");
    assert_eq!(words(c, plan.slave_mdt_data, 8), want);
}

// A slave powered on between telegrams, or behind a fibre repaired then, gets the filler
// upstream carries from that instant on (the simulation replays what enters its fibre): its
// receiver sees edges at once, so FIBBR (410B §4.1 2H.13, "No edges on receive data") does
// not rise while it waits for the next telegram, as it does while its fibre is dark
// (`power_off_and_on_of_a_slave`). The same on the fast path, where slaves otherwise get no
// other slave's signal, as on the exact one.
#[test]
fn a_slave_powered_on_between_telegrams_hears_the_filler_at_once() {
    // With the telegram log on (every fibre traced) and without any trace.
    for (delivery, logged) in [
        (Delivery::Fast, true),
        (Delivery::Exact, true),
        (Delivery::Fast, false),
    ] {
        let mut ring = StaticRing::new(4, 250);
        ring.delivery = delivery;
        for on_us in [2100u64, 2130, 2170, 2210] {
            // Slave 2 powered off, or the fibre into it (segment 1, from slave 1) broken.
            for powered_off in [true, false] {
                let (mut cfg, hosts, _) = build(&ring);
                if !logged {
                    cfg.traces.log = None;
                }
                let until = Some(us(on_us));
                let kind = if powered_off {
                    FaultKind::PowerOff { node: 2, until }
                } else {
                    FaultKind::FibreBreak { segment: 1, until }
                };
                cfg.faults = vec![Fault { at: us(1000), kind }];
                let mut sim = Simulation::new(cfg, hosts).expect("valid");
                let case = format!("{delivery:?} (logged {logged}, {kind:?})");
                sim.run_until(us(on_us - 10)).expect("runs");
                assert_ne!(sim.powered(2), powered_off, "{case}");
                let dark = if powered_off { 3 } else { 2 };
                assert!(
                    reg(&mut sim, dark, Register::Ctrl2) & FIBBR != 0,
                    "{case}: dark downstream"
                );
                // Every 500 ns up to 5 µs after (FIBBR_BIT_TIMES at 16 Mbit/s is 2 µs): the
                // filler only. A repaired fibre's light takes its delay (50 ns) to arrive.
                let first = u64::from(!powered_off);
                for k in first..=10u64 {
                    sim.run_until(us(on_us) + Duration::from_nanos(500 * k))
                        .expect("runs");
                    assert!(sim.powered(2));
                    assert_eq!(
                        reg(&mut sim, 2, Register::Ctrl2) & FIBBR,
                        0,
                        "{case}: on at {on_us} µs, {} ns after",
                        500 * k
                    );
                }
            }
        }
    }
}

#[test]
fn drifting_clock_stays_synchronised_to_the_mst() {
    // Slave 2's MCLK runs 2000 ppm fast, then (fault at 1.5 ms) 2000 ppm slow. Its AT
    // comes TRT of *its* µs after the MST's end: off by TRT × error, never accumulating
    // over cycles (410B §4.1 0CH: the slave's cycle follows the MST).
    let ring = StaticRing::new(2, 250);
    let (mut cfg, hosts, plan) = build(&ring);
    if let Some(n) = cfg.nodes.get_mut(2) {
        n.mclk_error_ppm = 2000.0;
    }
    cfg.faults = vec![Fault {
        at: us(1500),
        kind: FaultKind::ClockDrift {
            node: 2,
            ppm: -2000.0,
        },
    }];
    let bt = ring.bit_rate.bit_time();
    let (mut sim, out) = run(cfg, hosts, us(3000));
    let lines = parse_log(&out.log);
    let mst_bits = frame_bit_len(&[255, 4]);
    let trt_ps = u64::from(plan.at_trt_us[1]) * 1_000_000;
    let shift = (trt_ps as f64 * 2000e-6) as u64; // ≈ 94 ns
    // From MST end at slave 2 to its AT entering segment 2: nominally TRT.
    let d02 = sim.ring_delay(0, 2, bt).expect("ring");
    let msts: Vec<u64> = lines
        .iter()
        .filter(|l| l.seg == 0 && l.kind == "MST")
        .map(|l| l.ps)
        .collect();
    let mut seen = (0, 0);
    for s in msts {
        let Some(at) = lines
            .iter()
            .find(|l| l.seg == 2 && l.kind == "AT" && l.adr == Some(2) && l.ps > s)
        else {
            continue;
        };
        if at.ps > s + 250_000_000 {
            continue;
        }
        let end = s + bt.saturating_mul(mst_bits).as_picos() + d02.as_picos();
        let off = at.ps as i64 - (end + trt_ps) as i64;
        let tol = 31_250 + bt.as_picos() as i64;
        if s < 1_500_000_000 {
            // Fast clock: its µs are short, the AT comes early.
            assert!((off + shift as i64).abs() <= tol, "fast: off {off}");
            seen.0 += 1;
        } else if s > 1_600_000_000 {
            assert!((off - shift as i64).abs() <= tol, "slow: off {off}");
            seen.1 += 1;
        }
    }
    assert!(seen.0 >= 4 && seen.1 >= 4, "{seen:?}");
    assert_eq!(nerr_master(&mut sim, &plan, 2).0, 0);
    let _ = REPEATER_LATENCY_BITS;
}

#[test]
fn distortion_sets_rdist_at_the_receiver_only() {
    let ring = StaticRing::new(3, 250);
    let (mut sim, _) = sim_with(
        &ring,
        vec![Fault {
            at: us(1000),
            kind: FaultKind::Distortion {
                segment: 1,
                until: us(1300),
            },
        }],
    );
    sim.run_until(us(900)).expect("runs");
    clear_ints(&mut sim);
    sim.run_until(us(1100)).expect("runs");
    // 410B §4.1 2H.12 RDIST while the signal is distorted, 4H.0 INT_RDIST; the repeater
    // regenerates (410B §1), so slave 3 and the master see a clean signal.
    assert!(reg(&mut sim, 2, Register::IntFlagsLo) & INT_RDIST != 0);
    for node in [0, 1, 3] {
        assert_eq!(
            reg(&mut sim, node, Register::IntFlagsLo) & INT_RDIST,
            0,
            "{node}"
        );
    }
    sim.run_until(us(1600)).expect("runs");
    assert_eq!(
        reg(&mut sim, 2, Register::Ctrl2) & RDIST,
        0,
        "RDIST ends with it"
    );
}

#[test]
fn rs485_bus_exchanges_and_reports_collisions() {
    // 410B Fig. 4: every node hears every transmitter.
    let mut ring = StaticRing::new(2, 250);
    ring.repon = false;
    let (mut cfg, hosts, plan) = build(&ring);
    cfg.topology = Topology::Bus {
        delay: Duration::from_nanos(50),
    };
    let (mut sim, out) = run(cfg, hosts, us(1500));
    assert_eq!(sim.stats().collisions, 0);
    for s in 1..=2 {
        let (nerr, rerr, val) = nerr_master(&mut sim, &plan, s);
        assert!(nerr == 0 && !rerr && val, "AT {s}");
    }
    assert!(parse_log(&out.log).iter().all(|l| l.ok && l.seg == 0));
    // Both slaves answer at the same TRT: the transmissions overlap.
    ring.repon = false;
    let t = StaticRing::new(2, 250).build().expect("fits").2.at_trt_us[0];
    ring.at_trt_override = Some(vec![t, t]);
    let (mut cfg, hosts, plan) = build(&ring);
    cfg.topology = Topology::Bus {
        delay: Duration::from_nanos(50),
    };
    let (mut sim, out) = run(cfg, hosts, us(1500));
    assert!(sim.stats().collisions >= 4);
    assert!(parse_log(&out.log).iter().any(|l| !l.ok));
    let errs: u16 = (1..=2).map(|s| nerr_master(&mut sim, &plan, s).0).sum();
    assert!(errs >= 4, "{errs}");
    let _ = Instant::ZERO;
}

// 410B §1; spec-notes "Own clocks". Slave 1 starts to drift (+2000 ppm) 10 µs into an MST it
// receives (2 Mbit/s: the MST lasts 24.5 µs). The master's filler follows the MST at once, so
// in slave 1's time it starts where the MST's bits end, as on the fast path, where the MST
// carries its filler and came before the drift. Mapped alone by the drifting clock on the
// reference path, it started 29 ns later (the MST's remaining 14.5 µs × 2000 ppm): every
// filler edge slave 1 saw and repeated lay 29 ns apart on the two paths.
#[test]
fn a_clock_that_starts_to_drift_inside_a_telegram_keeps_its_filler_behind_it() {
    let mut ring = StaticRing::new(2, 1000);
    ring.bit_rate = sercos_wire::time::BitRate::Mbit2;
    ring.mdt_after_ats = true;
    let bt = ring.bit_rate.bit_time();
    let (cfg, hosts, _) = build(&ring);
    let (_, out) = run(cfg, hosts, us(4100));
    let mst = parse_log(&out.log)
        .into_iter()
        .find(|l| l.seg == 0 && l.kind == "MST" && l.ps > 4_000_000_000)
        .expect("cycle 4's MST")
        .ps;
    let sim_probe = {
        let (cfg, hosts, _) = build(&ring);
        Simulation::new(cfg, hosts).expect("valid")
    };
    let delay = sim_probe.ring_delay(0, 1, bt).expect("ring");
    // Slave 1's time is the simulation's until the drift starts, inside the MST.
    let start = Instant::from_picos(mst) + delay;
    let end = start + bt.saturating_mul(frame_bit_len(&[255, 4]));
    let drift_at = start + Duration::from_micros(10);
    let mut levels = Vec::new();
    for delivery in [Delivery::Exact, Delivery::Fast] {
        let mut r = ring.clone();
        r.delivery = delivery;
        let (mut cfg, hosts, _) = build(&r);
        cfg.faults = vec![Fault {
            at: drift_at,
            kind: FaultKind::ClockDrift {
                node: 1,
                ppm: 2000.0,
            },
        }];
        let mut sim = Simulation::new(cfg, hosts).expect("valid");
        sim.run_until(end + Duration::from_micros(8)).expect("runs");
        let chip = sim.chip_mut(1).expect("slave 1");
        // 20 ns after each of the filler's first edges in slave 1's time.
        let seen: Vec<Option<bool>> = (0..8u64)
            .map(|k| chip.received_level_at(end + bt.saturating_mul(k) + Duration::from_nanos(20)))
            .collect();
        assert!(seen.iter().all(Option::is_some), "{delivery:?}: {seen:?}");
        levels.push(seen);
    }
    assert_eq!(levels[0], levels[1]);
    // The filler's edges: the level changes from each sample to the next.
    assert!(
        levels[0].windows(2).all(|w| w[0] != w[1]),
        "{:?}",
        levels[0]
    );
}
