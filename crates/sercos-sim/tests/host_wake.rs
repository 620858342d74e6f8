//! Host wakes follow level-triggered interrupt pins (410B §2 INT0/INT1: "Interrupt sources
//! and signal polarity are programmable"): a flag raised after the handler's last read of
//! 4H/5H keeps INT0 active without a new edge, and the host must still hear of it
//! (spec-notes "Ring simulation": one more wake when a pin is still active after an
//! interrupt wake). Regression: a master went deaf with INT0 stuck high.

use std::cell::RefCell;
use std::rc::Rc;

use sercon_model::ChipConfig;
use sercon_regs::{Register, SerconBus, SerconBusExt};
use sercos_sim::config::{NodeConfig, SimConfig};
use sercos_sim::topology::Topology;
use sercos_sim::{HostProgram, Simulation, Wake};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 5H.9 / 5H.10: INT_TIME0, INT_TIME1.
const TIME0_1: u16 = 0b11 << 9;

/// Programs a master timing control with TINT0 = 100 µs and TINT1 = 101 µs on INT0, and on
/// each interrupt reads 5H, clears what it saw, then spends 3 µs on other bus accesses.
struct Handler {
    seen: Rc<RefCell<Vec<u16>>>,
}

impl HostProgram for Handler {
    fn wake(&mut self, bus: &mut dyn SerconBus, _now: Instant, why: Wake) -> Option<Instant> {
        match why {
            Wake::Start | Wake::PowerOn => {
                // 410B §4.1: 0EH MCLKDIV (32 MHz → 1 µs), 0FH TSCYC0, 1AH/1BH TINT0/1,
                // 7H EN0 for 5H, 3H.1 ENINT0, 0CH MSTEN | MSTMASTER | CYCSTART.
                bus.write(Register::MclkDiv, 31);
                bus.write(Register::Tscyc0, 1000);
                bus.write(Register::Tint0, 100);
                bus.write(Register::Tint1, 101);
                bus.write(Register::En0IntHi, TIME0_1);
                bus.write(Register::Ctrl3, 1 << 1);
                bus.write(Register::Ctrl0C, 0x0403);
            }
            Wake::Interrupt { .. } => {
                let flags = bus.read_register(5) & TIME0_1;
                self.seen.borrow_mut().push(flags);
                bus.write_register(5, flags);
                for _ in 0..30 {
                    let _ = bus.read_register(0);
                }
            }
            Wake::Deadline => {}
        }
        None
    }
}

#[test]
fn a_flag_raised_after_the_last_read_still_wakes_the_host() {
    let seen = Rc::new(RefCell::new(Vec::new()));
    let mut node = NodeConfig::new("master", ChipConfig::sercon816());
    node.bus_access = Duration::from_nanos(100);
    let cfg = SimConfig {
        topology: Topology::ring(1, 10),
        nodes: vec![node],
        faults: Vec::new(),
        seed: 1,
        delivery: Default::default(),
        traces: Default::default(),
    };
    let host = Handler { seen: seen.clone() };
    let mut sim = Simulation::new(cfg, vec![Box::new(host)]).expect("one node");
    sim.run_until(Instant::from_picos(1_500_000_000))
        .expect("runs");
    let seen = seen.borrow();
    // Per cycle: TIME0 at 100 µs wakes the host; TIME1 rises at 101 µs while it is still busy
    // (INT0 stays active), and the extra wake picks it up.
    assert!(seen.len() >= 2, "{seen:?}");
    assert_eq!(seen[0], 1 << 9, "first wake sees INT_TIME0 only: {seen:?}");
    assert_eq!(seen[1], 1 << 10, "INT_TIME1 is still served: {seen:?}");
    // And the next cycle works the same (the host did not go deaf).
    assert!(
        seen.iter().filter(|f| **f == 1 << 9).count() >= 2,
        "{seen:?}"
    );
    let chip = sim.chip_mut(0).expect("node 0");
    assert_eq!(chip.read_register(5) & TIME0_1, 0, "every flag served");
}
