//! A repeater's carried copies (`Chip::set_forward_output(false)`) are followed, not released
//! (spec-notes "Forwarded copies carried", "Followed copies"; 410B §1 "The slaves regenerate
//! and repeat their received data or send their own telegrams"): the line's level an own
//! telegram continues from and the background resumed after one. A followed copy keeps
//! neither its hint nor inverted bits. Here the input is what a real sender releases (coded
//! telegrams with their hints and implied filler), so that copies arrive from either level
//! around the repeater's own telegrams, and a repeater that carries its copies must release
//! exactly what one that releases them does, less the copies, hints included.

use proptest::prelude::*;
use sercon_model::serial_port::LineSegment;
use sercon_model::{Chip, ChipConfig};
use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 2H: ENTXD1–6 on, normal transmit mode.
const ENTXD_ALL: u16 = 0x3F;
/// 410B §4.1 1H.3 REPON.
const REPON: u16 = 1 << 3;
/// 816 §2.3.1: ENTSBAUD = 1 with SWBAUD16 = SWBAUD = 0 selects 16 Mbit/s.
const ENTSBAUD: u16 = 1 << 10;
/// First byte of the upstream sender's telegrams (the repeater's own start with another).
const UPSTREAM: u8 = 0x55;
/// First byte of the repeater's own telegrams.
const OWN: u8 = 0xAA;

/// A SERCON816 at 16 Mbit/s, transmitter on, own telegrams with their implied filler.
fn chip(repon: bool) -> Chip {
    let mut c = Chip::new(ChipConfig::sercon816());
    c.write_register(1, ENTSBAUD | if repon { REPON } else { 0 });
    c.write_register(2, ENTXD_ALL);
    c.set_implied_filler(true);
    c
}

/// 16 Mbit/s.
fn bit_time() -> Duration {
    Duration::from_nanos(62) + Duration::from_picos(500)
}

/// A telegram: `gap` bit times after the previous one of the same sender ends, the
/// sender's first byte ([`UPSTREAM`] or [`OWN`]) then `rest`.
#[derive(Debug, Clone)]
struct Telegram {
    gap: u64,
    rest: Vec<u8>,
}

/// What the upstream sender releases for `telegrams`, in order.
fn upstream(telegrams: &[Telegram]) -> Vec<LineSegment> {
    let mut sender = chip(false);
    let bt = bit_time();
    let mut t = Instant::ZERO + Duration::from_micros(2);
    let mut out = Vec::new();
    for tg in telegrams {
        let at = t.max(sender.now()) + bt.saturating_mul(tg.gap);
        sender.advance_to(at);
        sender.take_line_output(&mut out);
        let mut bytes = vec![UPSTREAM];
        bytes.extend_from_slice(&tg.rest);
        if let Some(end) = sender.transmit_telegram(at, &bytes) {
            t = end;
        }
    }
    sender.advance_to(t.max(sender.now()) + Duration::from_micros(5));
    sender.take_line_output(&mut out);
    out
}

/// The segments a repeater releases for the upstream `input` (delayed by a fibre) and its
/// own telegrams, with its copies released or carried (`forward`), and its received frames.
fn repeater(
    input: &[LineSegment],
    own: &[Telegram],
    forward: bool,
) -> (Vec<LineSegment>, Vec<sercon_model::serial_port::RxFrame>) {
    let mut rep = chip(true);
    rep.set_forward_output(forward);
    let bt = bit_time();
    let delay = Duration::from_nanos(400);
    let mut out = Vec::new();
    let mut inputs = input.iter().map(|s| s.clone().delayed(delay)).peekable();
    let mut t_own = Instant::ZERO + Duration::from_micros(3);
    for tg in own {
        let at = t_own + bt.saturating_mul(tg.gap);
        // Every input segment that starts before the telegram, in order.
        while let Some(seg) = inputs.next_if(|s| s.start <= at) {
            rep.advance_to(seg.start.max(rep.now()));
            rep.take_line_output(&mut out);
            rep.line_input(seg);
        }
        rep.advance_to(at.max(rep.now()));
        rep.take_line_output(&mut out);
        let mut bytes = vec![OWN];
        bytes.extend_from_slice(&tg.rest);
        t_own = rep.transmit_telegram(at, &bytes).unwrap_or(at);
    }
    for seg in inputs {
        rep.advance_to(seg.start.max(rep.now()));
        rep.take_line_output(&mut out);
        rep.line_input(seg);
    }
    rep.advance_to(rep.now() + Duration::from_micros(20));
    rep.take_line_output(&mut out);
    let mut frames = Vec::new();
    rep.take_rx_frames(&mut frames);
    (out, frames)
}

/// Whether `seg` is a released copy of the upstream sender's signal: its telegrams (by their
/// hint's first byte) and its filler between them.
fn is_copy(seg: &LineSegment, copies: &[Instant]) -> bool {
    copies.contains(&seg.start)
        && seg
            .hint
            .as_ref()
            .is_none_or(|h| h.telegram.first() == Some(&UPSTREAM))
}

fn telegram() -> impl Strategy<Value = Telegram> {
    (0u64..300, proptest::collection::vec(any::<u8>(), 0..10))
        .prop_map(|(gap, rest)| Telegram { gap, rest })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(200)))]
    // 410B §1 "The slaves regenerate and repeat their received data or send their own
    // telegrams": a repeater that only follows its copies releases exactly the rest of what
    // it releases with them (own telegrams from the same level, what resumes after one), and
    // receives the same.
    #[test]
    fn followed_copies_leave_the_rest_of_the_output_unchanged(
        up in proptest::collection::vec(telegram(), 1..12),
        own in proptest::collection::vec(telegram(), 1..12),
    ) {
        let input = upstream(&up);
        let latency = bit_time().saturating_mul(sercon_model::serial_port::REPEATER_LATENCY_BITS);
        let delay = Duration::from_nanos(400);
        let copies: Vec<Instant> = input.iter().map(|s| s.start + delay + latency).collect();
        let (with, frames_with) = repeater(&input, &own, true);
        let (without, frames_without) = repeater(&input, &own, false);
        let rest: Vec<&LineSegment> = with.iter().filter(|s| !is_copy(s, &copies)).collect();
        let without: Vec<&LineSegment> = without.iter().collect();
        prop_assert_eq!(rest, without);
        prop_assert_eq!(frames_with, frames_without);
    }
}

/// A copy the repeater releases keeps the hint of the segment it copies (only a carried one,
/// which is never released, leaves it).
#[test]
fn a_released_copy_keeps_its_hint() {
    let input = upstream(&[Telegram {
        gap: 10,
        rest: vec![1, 2, 3],
    }]);
    let (out, _) = repeater(&input, &[], true);
    assert!(
        out.iter().any(|s| s
            .hint
            .as_ref()
            .is_some_and(|h| h.telegram.first() == Some(&UPSTREAM))),
        "{out:?}"
    );
}
