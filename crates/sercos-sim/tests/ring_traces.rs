//! Trace wiring: the telegram log (JSON lines), a pcapng capture of one segment and a VCD of
//! chosen pins of chosen nodes, all byte-identical for the same configuration and seed.

mod ring_support;

use ring_support::*;
use sercon_model::pins::{Pin, PinSet};
use sercos_sim::config::CaptureFormat;
use sercos_sim::recorder::TraceOutput;
use sercos_sim::static_ring::StaticRing;
use sercos_sim::trace::{LogFormat, SegmentId};
use sercos_sim::{Fault, FaultKind};

fn traced_run() -> TraceOutput {
    let ring = StaticRing::new(2, 250);
    let (mut cfg, hosts, _) = build(&ring);
    cfg.traces.log = Some(LogFormat::JsonLines);
    cfg.traces.hash = true;
    cfg.traces.capture = Some((SegmentId(2), CaptureFormat::PcapNg));
    // 410B §2: IDLE low while the node sends, REACTN low while it receives a telegram.
    cfg.traces.vcd = vec![
        (0, PinSet::of(&[Pin::Idle, Pin::Reactn])),
        (2, PinSet::of(&[Pin::Idle, Pin::Reactn, Pin::Int0])),
    ];
    cfg.faults = vec![Fault {
        at: us(600),
        kind: FaultKind::BitErrors {
            segment: 1,
            until: us(900),
            rate: 5e-4,
        },
    }];
    run(cfg, hosts, us(1000)).1
}

#[test]
fn traces_are_byte_identical_for_the_same_seed() {
    let a = traced_run();
    let b = traced_run();
    assert!(a.records > 20);
    assert_eq!(a, b);
    // JSON lines: one object per line.
    let log = String::from_utf8(a.log).expect("text");
    assert!(log.lines().all(|l| l.starts_with('{') && l.ends_with('}')));
    // pcapng: section header block magic; packets from segment 2 only.
    assert_eq!(a.capture.get(..4), Some(&[0x0A, 0x0D, 0x0D, 0x0A][..]));
    assert!(a.capture.len() > 500);
    // VCD: one scope per traced node, IDLE of the master toggles (it sends).
    let vcd = String::from_utf8(a.vcd).expect("text");
    assert!(vcd.contains("$scope module master $end"), "{vcd}");
    assert!(vcd.contains("$scope module slave2 $end"));
    assert!(vcd.matches('#').count() > 10);
}
