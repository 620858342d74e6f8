//! Property: arbitrary line input, register settings and transmit requests never panic or hang
//! the model, and what it reports stays ordered (410B §2 RxD/TxD; spec-notes "Serial port").

use proptest::prelude::*;
use sercon_model::pins::PinSet;
use sercon_model::serial_port::{FrameHint, LineSegment, LineSignal, Shared};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::SerconBus;
use sercos_wire::line::BitVec;
use sercos_wire::time::{Duration, Instant};

#[derive(Debug, Clone)]
enum Op {
    Input {
        gap_ns: i64,
        kind: u8,
        bits: Vec<bool>,
        bt_ps: u64,
        level_before: bool,
        hint: Option<Vec<u8>>,
        distorted: bool,
    },
    Write(u8, u16),
    Transmit(u64, Vec<u8>),
    Advance(u64),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        4 => (
            -2_000i64..20_000,
            0u8..4,
            proptest::collection::vec(any::<bool>(), 0..400),
            prop_oneof![Just(62_500u64), Just(125_000), Just(250_000), Just(500_000), 0u64..1_000_000],
            any::<bool>(),
            proptest::option::of(proptest::collection::vec(any::<u8>(), 0..12)),
            any::<bool>(),
        )
            .prop_map(|(gap_ns, kind, bits, bt_ps, level_before, hint, distorted)| Op::Input {
                gap_ns,
                kind,
                bits,
                bt_ps,
                level_before,
                hint,
                distorted,
            }),
        1 => (prop_oneof![Just(1u8), Just(2), Just(4), Just(3)], any::<u16>())
            .prop_map(|(a, v)| Op::Write(a, v)),
        2 => (0u64..30_000, proptest::collection::vec(any::<u8>(), 0..40))
            .prop_map(|(d, t)| Op::Transmit(d, t)),
        2 => (0u64..50_000).prop_map(Op::Advance),
    ]
}

proptest! {
    #[test]
    fn arbitrary_line_input_never_panics(ops in proptest::collection::vec(op(), 1..40), repon in any::<bool>()) {
        let mut cfg = ChipConfig::sercon816();
        cfg.straps.tm0 = repon;
        cfg.straps.tm1 = repon;
        let mut chip = Chip::new(cfg);
        chip.set_traced_pins(PinSet::ALL);
        let mut next = Instant::ZERO;
        let mut out = Vec::new();
        for op in ops {
            match op {
                Op::Input { gap_ns, kind, bits, bt_ps, level_before, hint, distorted } => {
                    let ps = next.as_picos().saturating_add_signed(gap_ns * 1000);
                    let start = Instant::from_picos(ps).max(chip.now());
                    let bt = Duration::from_picos(bt_ps);
                    let signal = match kind {
                        0 => {
                            let mut v = BitVec::new();
                            for b in &bits {
                                v.push(*b);
                            }
                            LineSignal::Bits(Shared::new(v))
                        }
                        1 => LineSignal::Filler,
                        2 => LineSignal::Dark,
                        _ => LineSignal::Light,
                    };
                    let seg = LineSegment {
                        start,
                        bit_time: bt,
                        signal,
                        level_before,
                        hint: hint.map(|t| Shared::new(FrameHint { telegram: t.into(), offset: bits.len() as u64 / 2, coded: None })),
                        distorted,
                        // Some telegrams carry their filler (LineSegment::then_filler).
                        then_filler: gap_ns % 3 == 0,
                    };
                    next = seg.end().unwrap_or(start);
                    chip.line_input(seg);
                }
                Op::Write(a, v) => chip.write_register(a, v),
                Op::Transmit(d, t) => {
                    let at = chip.now() + Duration::from_nanos(d);
                    if let Some(end) = chip.transmit_telegram(at, &t) {
                        prop_assert!(end > at);
                    }
                }
                Op::Advance(d) => {
                    let t = chip.now() + Duration::from_nanos(d);
                    chip.advance_to(t);
                    chip.take_line_output(&mut out);
                    let _ = chip.read_register(2);
                    let _ = chip.read_register(3);
                }
            }
        }
        let end = chip.now() + Duration::from_millis(1);
        chip.advance_to(end);
        chip.take_line_output(&mut out);
        prop_assert!(out.windows(2).all(|w| w[0].start <= w[1].start));
        let mut frames = Vec::new();
        chip.take_rx_frames(&mut frames);
        prop_assert!(frames.iter().all(|f| f.start <= f.end));
        let mut ev = Vec::new();
        chip.drain_pin_events(&mut ev);
        prop_assert!(ev.windows(2).all(|w| w[0].at <= w[1].at));
        let _ = chip.next_deadline();
    }
}
