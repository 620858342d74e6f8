//! A host's bus accesses take one access time each (`NodeConfig::bus_access`), and the ring
//! and the other hosts go on meanwhile, in time order (spec-notes "A host's bus time"): a host
//! woken while another is part way through its program runs beside it, not inside one of its
//! accesses, and neither waits for the other. Before (hosts nested), a host woken inside
//! another's access ran its whole program there and the busy host's next access came only
//! after it: in `sercon ring --drives 20 --baud 4 --cycle-us 2000` the master cleared
//! INT_COMEND (410B §4.1 4H.4, on INT0) 10.95 µs late on one path.

use std::cell::RefCell;
use std::rc::Rc;

use sercon_model::ChipConfig;
use sercon_regs::{Register, SerconBus, SerconBusExt};
use sercos_sim::config::{Delivery, NodeConfig, SimConfig};
use sercos_sim::topology::Topology;
use sercos_sim::{HostProgram, Simulation, Wake};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 5H.9 / 5H.10: INT_TIME0, INT_TIME1.
const TIME0: u16 = 1 << 9;
const TIME1: u16 = 1 << 10;

/// Programs a master timing control with MCLK at 32 MHz (one tick 31.25 ns), a cycle of
/// 1000 ticks, TINT0 = `tint0` and TINT1 = `tint1` ticks, `enabled` of 5H on INT0. On INT0
/// it reads 5H and clears what it saw; with `reread` it then reads 5H again and records
/// both reads.
struct Timer {
    tint0: u16,
    tint1: u16,
    enabled: u16,
    reread: bool,
    seen: Rc<RefCell<Vec<(u16, u16)>>>,
}

impl Timer {
    fn new(tint0: u16, tint1: u16, enabled: u16, reread: bool) -> Self {
        Timer {
            tint0,
            tint1,
            enabled,
            reread,
            seen: Rc::new(RefCell::new(Vec::new())),
        }
    }
}

impl HostProgram for Timer {
    fn wake(&mut self, bus: &mut dyn SerconBus, _now: Instant, why: Wake) -> Option<Instant> {
        match why {
            Wake::Start | Wake::PowerOn => {
                // 410B §4.1: 0EH MCLKDIV 0 (32 MHz), 0FH TSCYC0, 1AH/1BH TINT0/1, 7H EN0
                // for 5H, 3H.1 ENINT0, 0CH MSTEN | MSTMASTER | CYCSTART.
                bus.write(Register::MclkDiv, 0);
                bus.write(Register::Tscyc0, 1000);
                bus.write(Register::Tint0, self.tint0);
                bus.write(Register::Tint1, self.tint1);
                bus.write(Register::En0IntHi, self.enabled);
                bus.write(Register::Ctrl3, 1 << 1);
                bus.write(Register::Ctrl0C, 0x0403);
            }
            Wake::Interrupt { int0: true, .. } => {
                let flags = bus.read_register(5) & self.enabled;
                bus.write_register(5, flags);
                if self.reread {
                    let after = bus.read_register(5) & self.enabled;
                    self.seen.borrow_mut().push((flags, after));
                }
            }
            Wake::Interrupt { .. } | Wake::Deadline => {}
        }
        None
    }
}

/// Two nodes, 10 m fibres (50 ns), 100 ns per access; t0 = node a's TINT0. Node a reads 5H
/// at t0, clears INT_TIME0 at t0 + 100 ns and reads 5H again at t0 + 200 ns, before its TIME1
/// (tick 108, t0 + 250 ns): it reads nothing. Node b's TIME0 (t0 + 62.5 ns) wakes its host
/// inside a's accesses; b's write runs from t0 + 162.5 to t0 + 262.5 ns, a's TIME1 in its last
/// fibre. Run up to the access's end, it took in a's wake at TIME1 and moved a's chip on under
/// its host: a's second read came after TIME1 and saw INT_TIME1.
fn first_reads(delivery: Delivery) -> Vec<(u16, u16)> {
    let nodes: Vec<NodeConfig> = ["a", "b"]
        .iter()
        .map(|name| {
            let mut node = NodeConfig::new(name, ChipConfig::sercon816());
            node.bus_access = Duration::from_nanos(100);
            node
        })
        .collect();
    let cfg = SimConfig {
        topology: Topology::ring(2, 10),
        nodes,
        faults: Vec::new(),
        seed: 1,
        delivery,
        traces: Default::default(),
    };
    let a = Timer::new(100, 108, TIME0 | TIME1, true);
    let seen = a.seen.clone();
    let b = Timer::new(102, 900, TIME0, false);
    let mut sim = Simulation::new(cfg, vec![Box::new(a), Box::new(b)]).expect("two nodes");
    // Two cycles of 31.25 µs.
    sim.run_until(Instant::from_picos(70_000_000))
        .expect("runs");
    seen.take()
}

#[test]
fn a_host_s_access_leaves_the_busy_host_s_wake_past_its_reach() {
    for delivery in [Delivery::Fast, Delivery::Exact] {
        let seen = first_reads(delivery);
        assert!(seen.len() >= 2, "{delivery:?}: {seen:?}");
        assert_eq!(
            seen[0],
            (TIME0, 0),
            "{delivery:?}: INT_TIME0 cleared and 5H read again before TIME1: {seen:?}"
        );
    }
}

/// 410B §4.1 5H: the flags register a [`Worker`] clears and reads.
const REG_5H: u8 = 5;

/// What a [`Worker`] saw: the instant of each INT0 wake, 5H as its last access read it in
/// each, and how many wakes ended.
#[derive(Debug, Default)]
struct Seen {
    woke: Vec<Instant>,
    last_5h: Vec<u16>,
    ended: usize,
    power_on: usize,
}

/// A master timing control as [`Timer`] programs it (INT_TIME0 on INT0). On INT0 it clears
/// 5H, reads RAM words 0 to `reads - 1` (410B §4.2: the host's side of the dual-port RAM)
/// and reads 5H again: `reads + 3` accesses, the last one `reads + 2` access times after its
/// wake.
struct Worker {
    timer: Timer,
    reads: u16,
    seen: Rc<RefCell<Seen>>,
}

impl HostProgram for Worker {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        match why {
            Wake::Interrupt { int0: true, .. } => {
                self.seen.borrow_mut().woke.push(now);
                let flags = bus.read_register(REG_5H);
                bus.write_register(REG_5H, flags);
                for a in 0..self.reads {
                    bus.read_ram(a);
                }
                let last = bus.read_register(REG_5H);
                let mut seen = self.seen.borrow_mut();
                seen.last_5h.push(last);
                seen.ended += 1;
                None
            }
            Wake::PowerOn => {
                self.seen.borrow_mut().power_on += 1;
                self.timer.wake(bus, now, why)
            }
            _ => self.timer.wake(bus, now, why),
        }
    }
}

/// One bus access.
const ACCESS_NS: u64 = 100;

/// Nodes a and b on a ring of 10 m fibres, 100 ns per access, MCLK 32 MHz (31.25 ns a tick):
/// a's TINT0 at tick 100 with a program of 43 accesses, its last read of 5H 4.2 µs (134.4
/// ticks) after its wake, its TINT1 at `a_tint1`; b's TINT0 at tick 102 (62.5 ns after a's)
/// with a program of 253 accesses (25.3 µs, within the cycle of 31.25 µs), so that b is
/// woken while a is part way through.
fn workers(
    delivery: Delivery,
    a_tint1: u16,
    faults: Vec<sercos_sim::fault::Fault>,
) -> (Simulation, Rc<RefCell<Seen>>, Rc<RefCell<Seen>>) {
    workers_reading(delivery, a_tint1, (40, 250), faults)
}

/// [`workers`] with a's and b's programs reading `reads` RAM words.
fn workers_reading(
    delivery: Delivery,
    a_tint1: u16,
    reads: (u16, u16),
    faults: Vec<sercos_sim::fault::Fault>,
) -> (Simulation, Rc<RefCell<Seen>>, Rc<RefCell<Seen>>) {
    let pair = Pair {
        tint0_a: 100,
        tint1_a: a_tint1,
        tint0_b: 102,
        reads_a: reads.0,
        reads_b: reads.1,
        access_ns: ACCESS_NS,
        fibre_m: 10,
    };
    two_workers(delivery, &pair, faults)
}

/// Two [`Worker`]s, a on the master's place and b after it, on a ring of two fibres.
#[derive(Debug, Clone)]
struct Pair {
    /// a's TINT0 and TINT1 (ticks of 31.25 ns), b's TINT0.
    tint0_a: u16,
    tint1_a: u16,
    tint0_b: u16,
    /// RAM words each program reads.
    reads_a: u16,
    reads_b: u16,
    /// One bus access.
    access_ns: u64,
    /// Each fibre's length.
    fibre_m: u32,
}

/// The ring of `pair`, with `faults`, and each worker's record.
fn two_workers(
    delivery: Delivery,
    pair: &Pair,
    faults: Vec<sercos_sim::fault::Fault>,
) -> (Simulation, Rc<RefCell<Seen>>, Rc<RefCell<Seen>>) {
    let nodes: Vec<NodeConfig> = ["a", "b"]
        .iter()
        .map(|name| {
            let mut node = NodeConfig::new(name, ChipConfig::sercon816());
            node.bus_access = Duration::from_nanos(pair.access_ns);
            node
        })
        .collect();
    let cfg = SimConfig {
        topology: Topology::ring(2, pair.fibre_m),
        nodes,
        faults,
        seed: 1,
        delivery,
        traces: Default::default(),
    };
    let seen_a = Rc::new(RefCell::new(Seen::default()));
    let seen_b = Rc::new(RefCell::new(Seen::default()));
    let a = Worker {
        timer: Timer::new(pair.tint0_a, pair.tint1_a, TIME0, false),
        reads: pair.reads_a,
        seen: seen_a.clone(),
    };
    let b = Worker {
        timer: Timer::new(pair.tint0_b, 900, TIME0, false),
        reads: pair.reads_b,
        seen: seen_b.clone(),
    };
    let sim = Simulation::new(cfg, vec![Box::new(a), Box::new(b)]).expect("two nodes");
    (sim, seen_a, seen_b)
}

/// Each host's accesses come one access time apart though the other host is busy
/// meanwhile: a's last read of 5H, 42 accesses (4.2 µs) after its wake, comes after its
/// TIME1 at tick 234 (4.1875 µs after TIME0) and before its TIME1 at tick 235 (4.21875 µs),
/// not after b's 253 accesses; b is woken while a is at work. 410B §4.1 5H.9/5H.10 flags.
#[test]
fn busy_hosts_run_side_by_side_each_access_one_access_time_after_the_last() {
    for delivery in [Delivery::Fast, Delivery::Exact] {
        for (tint1, seen_time1) in [(234, true), (235, false)] {
            let (mut sim, seen_a, seen_b) = workers(delivery, tint1, Vec::new());
            sim.run_until(Instant::from_picos(30_000_000))
                .expect("runs");
            let a = seen_a.borrow();
            let b = seen_b.borrow();
            let (Some(t_a), Some(t_b)) = (a.woke.first(), b.woke.first()) else {
                panic!("{delivery:?}: both woken: {a:?} {b:?}");
            };
            let last_a = t_a.saturating_add(Duration::from_nanos(42 * ACCESS_NS));
            assert!(
                t_b > t_a && *t_b < last_a,
                "{delivery:?}: b ({t_b:?}) is woken while a ({t_a:?}) is at work"
            );
            assert_eq!(
                a.last_5h.first().map(|f| f & TIME1 != 0),
                Some(seen_time1),
                "{delivery:?}, TINT1 {tint1}: a's last read at its wake + 4.2 µs: {a:?}"
            );
            assert_eq!(b.ended, 1, "{delivery:?}: {b:?}");
        }
    }
}

/// A node powered off while its host waits in an access: the host's wake ends on the chip
/// alone, and the program starts over at power-on (`Wake::PowerOn`) and takes its interrupts
/// again; nothing panics and both paths agree.
#[test]
fn a_host_waiting_in_an_access_at_a_power_off_ends_its_wake_and_starts_over() {
    use sercos_sim::fault::{Fault, FaultKind};
    let mut wakes = Vec::new();
    for delivery in [Delivery::Fast, Delivery::Exact] {
        // b is woken ≈ 3.8 µs into the run and works for 25.3 µs: off from 10 µs
        // to 20 µs, in the middle of its program.
        let off = Fault {
            at: Instant::from_picos(10_000_000),
            kind: FaultKind::PowerOff {
                node: 1,
                until: Some(Instant::from_picos(20_000_000)),
            },
        };
        let (mut sim, _seen_a, seen_b) = workers(delivery, 900, vec![off]);
        sim.run_until(Instant::from_picos(9_000_000)).expect("runs");
        assert_eq!(seen_b.borrow().woke.len(), 1, "{delivery:?}: b at work");
        sim.run_until(Instant::from_picos(200_000_000))
            .expect("runs");
        let seen = seen_b.borrow();
        assert_eq!(seen.power_on, 1, "{delivery:?}");
        assert!(
            seen.woke.len() >= 3 && seen.ended == seen.woke.len(),
            "{delivery:?}: b takes its interrupts again after power-on: {seen:?}"
        );
        wakes.push(seen.woke.clone());
    }
    assert_eq!(wakes[0], wakes[1], "both paths wake b alike");
}

/// `run_until` returns with no host left part way through a wake: b's program of 25.3 µs,
/// begun at ≈ 3.8 µs, has ended when a run up to 5 µs returns, its chip past its last
/// access.
#[test]
fn a_run_returns_with_every_host_program_ended() {
    for delivery in [Delivery::Fast, Delivery::Exact] {
        let (mut sim, _seen_a, seen_b) = workers(delivery, 900, Vec::new());
        sim.run_until(Instant::from_picos(5_000_000)).expect("runs");
        let b = seen_b.borrow();
        assert_eq!((b.woke.len(), b.ended), (1, 1), "{delivery:?}: {b:?}");
        let end = b.woke[0].saturating_add(Duration::from_nanos(253 * ACCESS_NS));
        let chip_now = sim.chip_mut(1).map(|c| c.now());
        assert!(
            chip_now >= Some(end),
            "{delivery:?}: b's chip at {chip_now:?}"
        );
    }
}

/// Two workers with any timers, programs and access time (leaving an instant in each cycle
/// at which neither is at work), on any fibres: the run is the same whether `run_until` is called in steps of any length (each ending with every host
/// program run to its end) or once, on both paths: every wake, every last read of 5H, both
/// chips' registers and RAM words 0..64 and DONE words.
mod stepped {
    use super::*;
    use proptest::prelude::*;

    /// What a run leaves: each worker's wakes and last reads of 5H, both chips' state.
    #[derive(Debug, PartialEq)]
    struct Outcome {
        a: (Vec<Instant>, Vec<u16>),
        b: (Vec<Instant>, Vec<u16>),
        chips: Vec<u16>,
    }

    /// What a run leaves.
    fn outcome(delivery: Delivery, p: &Pair, steps: &[u64]) -> Outcome {
        let (mut sim, seen_a, seen_b) = two_workers(delivery, p, Vec::new());
        let end = 3 * 31_250_000u64;
        let mut t = 0u64;
        for s in steps.iter().cycle() {
            t = (t + s).min(end);
            sim.run_until(Instant::from_picos(t)).expect("runs");
            if t == end {
                break;
            }
        }
        let mut chips = Vec::new();
        for i in 0..2 {
            let chip = sim.chip_mut(i).expect("a node");
            chips.extend((0u8..0x2B).map(|r| chip.read_register(r)));
            chips.extend((0u16..64).map(|w| chip.read_ram(w)));
        }
        let (a, b) = (seen_a.borrow(), seen_b.borrow());
        Outcome {
            a: (a.woke.clone(), a.last_5h.clone()),
            b: (b.woke.clone(), b.last_5h.clone()),
            chips,
        }
    }

    /// Programs of at most 63 accesses of at most 200 ns (12.6 µs) each, once a cycle of
    /// 31.25 µs: the two together cannot cover the cycle, so there is an instant in every
    /// cycle at which neither is at work and a run can stop (`run_until`).
    fn params() -> impl Strategy<Value = Pair> {
        (
            50u16..600,
            50u16..900,
            50u16..600,
            0u16..60,
            0u16..60,
            20u64..200,
            1u32..200,
        )
            .prop_map(
                |(tint0_a, tint1_a, tint0_b, reads_a, reads_b, access_ns, fibre_m)| Pair {
                    tint0_a,
                    tint1_a,
                    tint0_b,
                    reads_a,
                    reads_b,
                    access_ns,
                    fibre_m,
                },
            )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(
            std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(24)
        ))]

        #[test]
        fn busy_hosts_run_the_same_in_any_steps(
            p in params(),
            steps in proptest::collection::vec(100_000u64..7_000_000, 1..6),
        ) {
            for delivery in [Delivery::Fast, Delivery::Exact] {
                let whole = outcome(delivery, &p, &[u64::MAX / 4]);
                let stepped = outcome(delivery, &p, &steps);
                prop_assert_eq!(&whole, &stepped, "{:?} {:?}", delivery, p);
                prop_assert!(!whole.a.0.is_empty() && !whole.b.0.is_empty(), "both woken: {:?}", p);
            }
        }
    }
}

/// Hosts whose work never leaves them a break (programs of 40.3 µs woken every 31.25 µs,
/// side by side so that they wait in their accesses; each is woken again for the TIME0
/// that came while it worked, its INT0 low and high again meanwhile, 410B §2 level
/// outputs): `run_until` cannot return between their wakes and says so
/// ([`sercos_sim::sim::HOST_BREAK_LIMIT`] after the instant asked for), in finite time.
#[test]
fn a_host_never_between_wakes_is_an_error_not_a_hang() {
    // One path: 100 ms of busy hosts take a while in a debug build.
    let (mut sim, seen_a, _) = workers_reading(Delivery::Fast, 900, (400, 400), Vec::new());
    let err = sim
        .run_until(Instant::from_picos(1_000_000_000))
        .expect_err("never between wakes");
    assert!(
        matches!(err, sercos_sim::SimError::HostNeverIdle { .. }),
        "{err}"
    );
    // 100 ms of programs of 40.3 µs, back to back.
    assert!(
        seen_a.borrow().ended > 2000,
        "it kept working: {}",
        seen_a.borrow().ended
    );
}
