//! The output queries a ring simulation uses to skip wakes: `Chip::next_internal_event_at`
//! and `Chip::next_line_output_except` (410B §1: "The slaves regenerate and repeat their
//! received data"; §4.1 1H.3 REPON).

use sercon_model::config::Straps;
use sercon_model::serial_port::{LineSegment, LineSignal, REPEATER_LATENCY_BITS};
use sercon_model::{Chip, ChipConfig};
use sercos_wire::time::{BitRate, Duration, Instant};

fn us(n: u64) -> Instant {
    Instant::ZERO + Duration::from_micros(n)
}

/// A SERCON816 with TM0 = TM1 = 1: no test mode, the repeater on after reset (816 §2.3.3).
fn repeater() -> Chip {
    let mut cfg = ChipConfig::sercon816();
    cfg.straps = Straps::NORMAL;
    Chip::new(cfg)
}

#[test]
fn expected_forwarded_copies_are_left_out_and_others_are_not() {
    let mut chip = repeater();
    chip.advance_to(us(1));
    let mut out = Vec::new();
    chip.take_line_output(&mut out);
    let bt = BitRate::Mbit16.bit_time();
    let latency = bt.saturating_mul(REPEATER_LATENCY_BITS);
    // Two filler segments arrive ahead of time: the repeater queues both, 2 bit times later.
    chip.line_input(LineSegment::steady(us(3), bt, LineSignal::Filler, false));
    chip.line_input(LineSegment::steady(us(5), bt, LineSignal::Dark, true));
    let first = us(3) + latency;
    let second = us(5) + latency;
    assert_eq!(chip.next_line_output_at(), Some(first));
    assert_eq!(chip.next_line_output_except([]), Some(first));
    // The first copy is expected: the second is the next output to wake for.
    assert_eq!(chip.next_line_output_except([first]), Some(second));
    // Expected instants that match nothing are passed over.
    assert_eq!(
        chip.next_line_output_except([us(2), first, us(4)]),
        Some(second)
    );
    assert_eq!(chip.next_line_output_except([first, second]), None);
    assert_eq!(chip.next_line_output_except([second]), Some(first));
    // Without an own telegram or a resume, the internal events come without the output.
    let internal = chip.next_internal_event_at();
    let all = chip.next_event_at();
    assert_eq!(
        all,
        [internal, Some(first)].into_iter().flatten().min(),
        "next_event_at = internal events and output"
    );
}

#[test]
fn own_telegrams_always_count() {
    let mut chip = repeater();
    chip.advance_to(us(1));
    let mut out = Vec::new();
    chip.take_line_output(&mut out);
    // 410B §1: the chip sends its own telegram at 10 µs; a copy it expects cannot hide it.
    let end = chip.transmit_telegram(us(10), &[1, 2, 3]);
    assert!(end.is_some(), "the repeater sends own telegrams too");
    assert_eq!(chip.next_line_output_except([us(10)]), Some(us(10)));
    assert_eq!(chip.next_line_output_except([]), Some(us(10)));
}
