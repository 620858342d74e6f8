//! Light wakes ([`Simulation::wake_node`]) against the full serve of every wake: the same
//! telegrams on every fibre, the same counters, the same chips, with faults and with hosts
//! that follow interrupts and deadlines.

use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

use super::Simulation;
use super::test_state::chip_words;
use crate::config::Delivery;
use crate::fault::{Fault, FaultKind};
use crate::host::{HostProgram, Wake};
use crate::static_ring::StaticRing;
use crate::trace::LogFormat;

fn us(n: u64) -> Instant {
    Instant::ZERO + Duration::from_micros(n)
}

/// Wraps a static ring's host: on every interrupt it reads 3H (410B §4.1 INTFL0/INTFL1) and
/// the status register, and it asks to be woken every `period`.
struct Polling {
    inner: Box<dyn HostProgram>,
    period: Duration,
}

impl HostProgram for Polling {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        self.inner.wake(bus, now, why);
        if matches!(why, Wake::Interrupt { .. } | Wake::Deadline) {
            bus.read_register(3);
            bus.read_register(2);
        }
        Some(now.saturating_add(self.period))
    }
}

/// Runs a 6-slave ring (fast or exact path, text log on every fibre, faults) to `until`,
/// light wakes on or off, polling hosts on slaves 2 and 5 if `polling`.
fn run(
    delivery: Delivery,
    light: bool,
    polling: bool,
    until: Instant,
) -> (Vec<u8>, super::SimStats, Vec<u16>) {
    let mut ring = StaticRing::new(6, 250);
    ring.delivery = delivery;
    ring.fibre_m = 30;
    ring.mdt_words = 2;
    ring.at_words = 2;
    let Ok((mut cfg, hosts, _)) = ring.build() else {
        panic!("the ring fits");
    };
    cfg.traces.log = Some(LogFormat::Text);
    cfg.faults = vec![
        Fault {
            at: us(310),
            kind: FaultKind::BitErrorBurst {
                segment: 3,
                bits: 40,
            },
        },
        Fault {
            at: us(400),
            kind: FaultKind::ClockDrift { node: 4, ppm: 80.0 },
        },
        Fault {
            at: us(600),
            kind: FaultKind::PowerOff {
                node: 2,
                until: Some(us(750)),
            },
        },
    ];
    let hosts: Vec<Box<dyn HostProgram>> = hosts
        .into_iter()
        .enumerate()
        .map(|(i, h)| -> Box<dyn HostProgram> {
            if polling && (i == 2 || i == 5) {
                Box::new(Polling {
                    inner: h,
                    period: Duration::from_micros(37),
                })
            } else {
                h
            }
        })
        .collect();
    let Ok(mut sim) = Simulation::new(cfg, hosts) else {
        panic!("the simulation builds");
    };
    sim.light_wakes = light;
    assert!(sim.run_until(until).is_ok());
    let stats = sim.stats();
    let regs = chip_words(&mut sim, 0);
    let Ok(out) = sim.finish() else {
        panic!("the traces end");
    };
    (out.log, stats, regs)
}

#[test]
fn light_wakes_give_the_same_run_as_full_serves() {
    for delivery in [Delivery::Fast, Delivery::Exact] {
        for polling in [false, true] {
            let full = run(delivery, false, polling, us(1100));
            let light = run(delivery, true, polling, us(1100));
            assert!(full.0.len() > 1000, "{delivery:?}: a log was written");
            assert_eq!(
                String::from_utf8_lossy(&full.0),
                String::from_utf8_lossy(&light.0),
                "{delivery:?} polling {polling}"
            );
            assert_eq!(full.1, light.1, "{delivery:?} polling {polling}");
            assert_eq!(full.2, light.2, "{delivery:?} polling {polling}");
        }
    }
}
