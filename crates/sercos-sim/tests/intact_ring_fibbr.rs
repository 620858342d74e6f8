//! An intact ring has light everywhere: no node's receiver may report FIBBR (410B §4.1
//! 2H.13 "No edges on receive data", 4H.1 INT_FIBBR), whatever its host does, and every
//! line segment reaches its chip before the chip's clock passes its start (the contract of
//! `Chip::line_input`; `SimStats::late`). Regression: a host working through many bus
//! accesses ran its chip ahead of the line, and the master saw its own returning signal too
//! late (spec-notes "Ring simulation": hosts run with the ring).

mod ring_support;

use ring_support::*;
use sercon_regs::value::interrupt::IntFlagsLo;
use sercon_regs::{Register, SerconBusExt};
use sercos_sim::static_ring::StaticRing;
use sercos_sim::{Delivery, Simulation};
use sercos_wire::time::{BitRate, Duration};

/// Bus accesses of one busy host run: 200 × 100 ns = 20 µs, as long as a driver's cycle work.
const BUSY_ACCESSES: u16 = 200;

/// Runs an intact ring of 8 slaves with busy hosts for `cycles` cycles and checks that no
/// node latched INT_FIBBR after the start and no segment came late.
fn intact_ring_stays_lit(rate: BitRate, cycle_us: u16, delivery: Delivery, cycles: u64) {
    let label = format!("{rate:?} {cycle_us} µs {delivery:?}");
    let mut ring = StaticRing::new(8, cycle_us);
    ring.bit_rate = rate;
    ring.delivery = delivery;
    let cycle = Duration::from_micros(u64::from(cycle_us));
    let (cfg, hosts, _plan) = ring.build().expect("the ring fits");
    // Every host busy once a cycle, 3.3 µs later in the cycle each time (sweeps the cycle).
    let period = cycle.saturating_add(Duration::from_nanos(3_300));
    let hosts = reading_hosts(hosts, period, BUSY_ACCESSES);
    let mut sim = Simulation::new(cfg, hosts).expect("a valid ring");
    // Dark until the first signal arrives (spec-notes "Serial port"): FIBBR after reset.
    sim.run_until(us(0) + cycle.saturating_mul(4))
        .expect("runs");
    let late_at_start = sim.stats().late;
    let nodes = sim.node_count();
    for i in 0..nodes {
        let chip = sim.chip_mut(i).expect("a node");
        chip.clear_int_lo(IntFlagsLo::INT_FIBBR);
    }
    sim.run_until(us(0) + cycle.saturating_mul(cycles))
        .expect("runs");
    for i in 0..nodes {
        let chip = sim.chip_mut(i).expect("a node");
        let flags = chip.read(Register::IntFlagsLo);
        assert_eq!(
            flags & IntFlagsLo::INT_FIBBR.bits(),
            0,
            "{label}: node {i} saw no edges (4H = {flags:#06x})"
        );
    }
    assert_eq!(
        sim.stats().late,
        late_at_start,
        "{label}: segments delivered late"
    );
}

// 410B §4.1 2H.13 FIBBR, 4H.1 INT_FIBBR: at 16 Mbit/s / 250 µs (issue acceptance ring).
#[test]
fn no_fibbr_on_an_intact_ring_at_16_mbit() {
    for delivery in [Delivery::Fast, Delivery::Exact] {
        intact_ring_stays_lit(BitRate::Mbit16, 250, delivery, 100);
    }
}

// 410B §4.1 2H.13 FIBBR at 8 and 4 Mbit/s (816 §2.3.1 rates).
#[test]
fn no_fibbr_on_an_intact_ring_at_8_and_4_mbit() {
    intact_ring_stays_lit(BitRate::Mbit8, 500, Delivery::Fast, 60);
    intact_ring_stays_lit(BitRate::Mbit4, 1000, Delivery::Fast, 40);
}
