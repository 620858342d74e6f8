//! Hosts that keep their bus busy change nothing on the line. A RAM read has no effect on
//! the controller (410B §4.2: the dual-port RAM is read by the host without side effects)
//! and a real chip keeps sending and receiving while its host works (410B §1), so a static
//! ring whose hosts all read RAM for a while each cycle — all of them at the same instant,
//! each woken inside the others' bus time — must put exactly the telegrams on every fibre
//! that the same ring with idle hosts does. The simulation runs the ring along while a host
//! works, each host waiting in its accesses (`sim/host_run.rs`): a chip moved on too far
//! under its host would take segments late or put its output on the line late, and the log
//! would differ.

mod ring_support;

use ring_support::*;
use sercos_sim::Delivery;
use sercos_sim::static_ring::StaticRing;
use sercos_wire::time::{BitRate, Duration};

/// The text log and the late count of `ring` run for `cycles` cycles with hosts reading
/// `accesses` words each period (every host at the same instants).
fn run_with(ring: &StaticRing, accesses: u16, cycles: u64) -> (Vec<u8>, u64) {
    let (cfg, hosts, _plan) = build(ring);
    let cycle = Duration::from_micros(u64::from(ring.cycle_us));
    // 1.7 µs later in the cycle each time: the busy time sweeps MST, MDT and the ATs.
    let period = cycle.saturating_add(Duration::from_nanos(1_700));
    let hosts = reading_hosts(hosts, period, accesses);
    let (sim, out) = run(cfg, hosts, us(0) + cycle.saturating_mul(cycles));
    (out.log, sim.stats().late)
}

/// Checks that busy hosts leave the log of `ring` as idle hosts do.
fn busy_hosts_change_nothing(ring: &StaticRing, cycles: u64) {
    let label = format!("{:?} {} m {:?}", ring.bit_rate, ring.fibre_m, ring.delivery);
    let (idle, idle_late) = run_with(ring, 0, cycles);
    // 150 reads of 100 ns: 15 µs of bus time per host, longer than MST and MDT together.
    let (busy, busy_late) = run_with(ring, 150, cycles);
    assert!(
        parse_log(&idle).len() > 20,
        "{label}: the ring runs ({} telegrams)",
        parse_log(&idle).len()
    );
    assert_eq!(busy_late, idle_late, "{label}: segments delivered late");
    assert!(idle == busy, "{label}: busy hosts changed the line");
}

// 410B §1: the chip keeps receiving and repeating while its host works; 1 m fibres (5 ns,
// shorter than one access: many short steps) and 1 km fibres (5 µs: steps up to a fibre
// after the next event).
#[test]
fn busy_hosts_leave_the_line_as_idle_hosts_do_at_16_mbit() {
    for fibre_m in [1, 10, 1000] {
        let mut ring = StaticRing::new(6, 250);
        ring.fibre_m = fibre_m;
        busy_hosts_change_nothing(&ring, 30);
    }
}

// Reference path (every repeater's output taken hop by hop) and a slower line (816 §2.3.1).
#[test]
fn busy_hosts_leave_the_line_as_idle_hosts_do_exact_and_4_mbit() {
    let mut ring = StaticRing::new(4, 250);
    ring.delivery = Delivery::Exact;
    busy_hosts_change_nothing(&ring, 20);
    let mut ring = StaticRing::new(4, 1000);
    ring.bit_rate = BitRate::Mbit4;
    ring.fibre_m = 200;
    busy_hosts_change_nothing(&ring, 12);
}
