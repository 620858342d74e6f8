//! A host's access runs the other nodes' events only as far as they can reach its chip
//! within the access (a fibre before its end, `sim/host_run.rs`), as the quiet-access
//! shortcut does. Regression: the long way ran every event up to the access's end. Run inside
//! a host woken within another host's access (hosts nest), that took in the busy host's own
//! wake, which moved its chip on under it, and its next access came that much late; whether
//! it happened hung on the quiet shortcut: in `sercon ring --drives 20 --baud 4 --cycle-us
//! 2000` the master cleared INT_COMEND (410B §4.1 4H.4, on INT0) 10.95 µs late on the
//! reference path only, the one VCD difference between the paths (spec-notes "Ring
//! simulation", "Events a host's access runs").

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
