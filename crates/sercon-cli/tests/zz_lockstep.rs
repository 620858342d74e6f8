use sercon_cli::ring::{self, RingSpec};
use sercos_sim::{Fault, FaultKind};
use sercos_wire::time::{Duration, Instant};

#[test]
fn zz_lockstep() {
    let mut spec = RingSpec::default();
    spec.drives = RingSpec::with_drives(7);
    spec.bit_rate = sercos_wire::time::BitRate::Mbit8;
    spec.cycle_us = 2000;
    spec.seed = 74;
    spec.traces.vcd = Some(std::path::PathBuf::from("/tmp/zz.vcd"));
    let t = |us: u64| Instant::ZERO.saturating_add(Duration::from_micros(us));
    let faults = || {
        vec![Fault {
            at: t(2_837_005),
            kind: FaultKind::Distortion {
                segment: 1,
                until: t(2_857_005),
            },
        }]
    };
    let mut f = ring::build(&spec, faults(), true).unwrap();
    let mut spec_r = spec.clone();
    spec_r.reference = true;
    let mut r = ring::build(&spec_r, faults(), true).unwrap();
    let step = Duration::from_nanos(50);
    let mut at = t(2_796_100);
    f.sim.run_until(at).unwrap();
    r.sim.run_until(at).unwrap();
    while at < t(2_796_250) {
        at = at.saturating_add(step);
        f.sim.run_until(at).unwrap();
        r.sim.run_until(at).unwrap();
        let a = f.sim.chip_mut(0).unwrap();
        let (al, areg) = (a.pin_level(sercon_model::pins::Pin::Int0), a.zz_regs());
        let b = r.sim.chip_mut(0).unwrap();
        let (bl, breg) = (b.pin_level(sercon_model::pins::Pin::Int0), b.zz_regs());
        if al != bl {
            println!("{at:?} int0 {al} {bl}\n fast {areg}\n ref  {breg}");
        }
    }
}
