//! Two shortcuts a simulation may take on the line, and that they change nothing a chip
//! shows (spec-notes "Implied filler", "Forwarded copies carried"; 410B §1 repeater, §4.1
//! 2H.12 RDIST, 2H.13 FIBBR):
//!
//! * A telegram that carries the filler after it (`LineSegment::then_filler`,
//!   `Chip::set_implied_filler`) is the same line signal as the telegram and its filler as
//!   two segments. Two senders, identical but for the implied filler, send the same telegrams
//!   and repeat the same input (shadowed by their own telegrams, resumed after them: 410B §1
//!   "The slaves regenerate and repeat their received data or send their own telegrams");
//!   each feeds its own receiver, which also gets the same extra segments in the gaps. Both
//!   receivers (and both senders) must show the same frames, RAM, registers and pin levels.
//! * A repeater whose forwarded copies are carried by the simulation
//!   (`Chip::set_forward_output(false)`) releases exactly the rest of its output.

use proptest::prelude::*;
use sercon_model::pins::Pin;
use sercon_model::serial_port::{LineSegment, LineSignal, RxFrame, Shared};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::SerconBus;
use sercos_wire::line::BitVec;
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 2H: ENTXD1–6 on, normal transmit mode.
const ENTXD_ALL: u16 = 0x3F;
/// 410B §4.1 1H.3 REPON.
const REPON: u16 = 1 << 3;
/// 816 §2.3.1: ENTSBAUD = 1 with SWBAUD16 = SWBAUD = 0 selects 16 Mbit/s.
const ENTSBAUD: u16 = 1 << 10;
/// 410B §4.1 1H.9 POLTXD: light on when TxD = 1.
const POLTXD: u16 = 1 << 9;

/// What a chip shows: received frames, RAM, registers 00H–3FH, pin levels.
fn state(c: &mut Chip) -> (Vec<RxFrame>, Vec<u16>, Vec<u16>, Vec<bool>) {
    let mut frames = Vec::new();
    c.take_rx_frames(&mut frames);
    let ram = (0..2048).map(|a| c.read_ram(a)).collect();
    let regs = (0..0x40u8).map(|a| c.read_register(a)).collect();
    let pins = [
        Pin::Int0,
        Pin::Int1,
        Pin::Idle,
        Pin::Reactn,
        Pin::LErrn,
        Pin::TxD,
    ]
    .into_iter()
    .map(|p| c.pin_level(p))
    .collect();
    (frames, ram, regs, pins)
}

/// A SERCON816 at 16 Mbit/s (the bit time the test lines use), transmitter on.
fn chip(repon: bool) -> Chip {
    let mut c = Chip::new(ChipConfig::sercon816());
    c.write_register(1, ENTSBAUD | if repon { REPON } else { 0 });
    c.write_register(2, ENTXD_ALL);
    c
}

/// One thing that happens on the test line.
#[derive(Debug, Clone)]
enum Step {
    /// The sender sends `bytes` `gap` bit times after its last telegram's end (0:
    /// back to back).
    Send { gap: u64, bytes: Vec<u8> },
    /// The sender's receiver gets a segment (`kind`: filler, dark, light, bits) `gap` bit
    /// times after the previous one; repeated when REPON.
    Input { gap: u64, kind: u8, bits: Vec<bool> },
    /// The receivers get an extra segment `gap` (≥ 1) bit times after the end of the
    /// sender's last output and before its next: a second source on the line only in the
    /// gaps (spec-notes "Implied filler": inside a telegram it would cut the telegram and
    /// the filler it carries, which a separate filler segment would survive).
    Extra { gap: u64, kind: u8 },
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        3 => (0u64..80, proptest::collection::vec(any::<u8>(), 1..12))
            .prop_map(|(gap, bytes)| Step::Send { gap, bytes }),
        2 => (0u64..120, 0u8..4, proptest::collection::vec(any::<bool>(), 0..60))
            .prop_map(|(gap, kind, bits)| Step::Input { gap, kind, bits }),
        1 => (1u64..100, 0u8..3).prop_map(|(gap, kind)| Step::Extra { gap, kind }),
    ]
}

fn signal(kind: u8, bits: &[bool]) -> LineSignal {
    match kind {
        0 => LineSignal::Filler,
        1 => LineSignal::Dark,
        2 => LineSignal::Light,
        _ => {
            let mut v = BitVec::new();
            for b in bits {
                v.push(*b);
            }
            LineSignal::Bits(Shared::new(v))
        }
    }
}

/// The sender, its receiver down the fibre, and the receiver's line so far.
struct Line {
    sender: Chip,
    receiver: Chip,
    delay: Duration,
    out: Vec<LineSegment>,
    /// The end of what the receiver got last (the start of a steady segment).
    last_end: Instant,
}

impl Line {
    /// Advances the sender to `upto` and hands its output to the receiver.
    fn pass(&mut self, upto: Instant) {
        self.sender.advance_to(upto);
        self.sender.take_line_output(&mut self.out);
        for seg in self.out.drain(..) {
            let seg = seg.delayed(self.delay);
            self.last_end = self.last_end.max(seg.end().unwrap_or(seg.start));
            self.receiver.line_input(seg);
        }
    }
}

/// Runs the steps on a sender / receiver pair; the two chips at the end.
fn run(steps: &[Step], repon: bool, implied: bool) -> [Chip; 2] {
    let mut sender = chip(repon);
    sender.set_implied_filler(implied);
    let mut line = Line {
        sender,
        receiver: chip(false),
        delay: Duration::from_nanos(300),
        out: Vec::new(),
        last_end: Instant::ZERO,
    };
    let bt = Duration::from_nanos(62) + Duration::from_picos(500);
    let mut t_send = Instant::ZERO + Duration::from_micros(2);
    let mut t_in = t_send;
    for s in steps {
        match s {
            Step::Send { gap, bytes } => {
                let at = t_send.max(line.sender.now()) + bt.saturating_mul(*gap);
                line.pass(at);
                if let Some(end) = line.sender.transmit_telegram(at, bytes) {
                    t_send = end;
                }
            }
            Step::Input { gap, kind, bits } => {
                let at = t_in.max(line.sender.now()) + bt.saturating_mul(*gap);
                line.pass(at);
                let seg = LineSegment {
                    signal: signal(*kind, bits),
                    ..LineSegment::steady(at, bt, LineSignal::Filler, false)
                };
                t_in = seg.end().unwrap_or(at);
                line.sender.line_input(seg);
            }
            Step::Extra { gap, kind } => {
                // After everything the sender has released up to now.
                let now = line.sender.now();
                line.pass(now);
                let at = line.last_end.max(now + line.delay) + bt.saturating_mul(*gap);
                let at = at.max(line.receiver.now() + Duration::from_picos(1));
                // Only in a gap: not where the sender's next output arrives or later.
                if line
                    .sender
                    .next_line_output_at()
                    .is_some_and(|n| n + line.delay <= at)
                {
                    continue;
                }
                line.last_end = at;
                line.receiver
                    .line_input(LineSegment::steady(at, bt, signal(*kind, &[]), false));
            }
        }
    }
    let end = t_send.max(t_in).max(line.sender.now()) + Duration::from_micros(20);
    line.pass(end);
    line.receiver.advance_to(end + line.delay);
    [line.sender, line.receiver]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(200)))]
    #[test]
    fn implied_filler_leaves_every_chip_as_the_explicit_filler(
        steps in proptest::collection::vec(step(), 1..30),
        repon in any::<bool>(),
    ) {
        let mut explicit = run(&steps, repon, false);
        let mut implied = run(&steps, repon, true);
        for (i, (a, b)) in explicit.iter_mut().zip(implied.iter_mut()).enumerate() {
            prop_assert_eq!(a.now(), b.now());
            prop_assert_eq!(state(a), state(b), "chip {}", i);
        }
    }
}

/// The implied filler is taken back when the next segment starts where it would start:
/// a telegram followed at once by another is the same with and without it.
#[test]
fn back_to_back_telegrams_leave_no_filler_between_them() {
    let steps = [
        Step::Send {
            gap: 0,
            bytes: vec![1, 2, 3],
        },
        Step::Send {
            gap: 0,
            bytes: vec![4, 5],
        },
    ];
    let mut explicit = run(&steps, false, false);
    let mut implied = run(&steps, false, true);
    for (a, b) in explicit.iter_mut().zip(implied.iter_mut()) {
        assert_eq!(state(a), state(b));
    }
    let mut frames = Vec::new();
    implied[1].take_rx_frames(&mut frames);
    assert!(frames.is_empty(), "state() took them");
}

/// A sender with the implied filler sends one segment per telegram where the other sends
/// two, and what it sends stands for the same levels.
#[test]
fn one_segment_per_telegram_with_the_same_levels() {
    let mut a = chip(false);
    let mut b = chip(false);
    b.set_implied_filler(true);
    let t0 = Instant::ZERO + Duration::from_micros(2);
    let (mut oa, mut ob) = (Vec::new(), Vec::new());
    for k in 0..4u64 {
        let at = t0 + Duration::from_micros(10 * k);
        for c in [&mut a, &mut b] {
            c.advance_to(at);
            assert!(c.transmit_telegram(at, &[0x10, k as u8]).is_some());
        }
    }
    let end = t0 + Duration::from_micros(60);
    a.advance_to(end);
    b.advance_to(end);
    a.take_line_output(&mut oa);
    b.take_line_output(&mut ob);
    let bits = |v: &[LineSegment]| {
        v.iter()
            .filter(|s| matches!(s.signal, LineSignal::Bits(_)))
            .count()
    };
    assert_eq!(bits(&oa), 4);
    assert_eq!(bits(&ob), 4);
    assert!(ob.iter().filter(|s| s.then_filler).count() == 4);
    assert!(oa.len() > ob.len(), "{} vs {}", oa.len(), ob.len());
    // The levels agree at every bit boundary up to the end.
    let level = |v: &[LineSegment], t: Instant| {
        v.iter()
            .rev()
            .find(|s| s.start <= t)
            .is_some_and(|s| s.level_at(t))
    };
    let bt = Duration::from_nanos(62) + Duration::from_picos(500);
    let mut t = t0;
    while t < end {
        assert_eq!(level(&oa, t), level(&ob, t), "at {t:?}");
        t += bt;
    }
}

/// A receiver given `bits` (from `t0`) with an implied filler, then `next` at `gap_bits`
/// bit times after their end (0 or less: the filler had no time), advanced to `mid` in
/// between, against one given the explicit filler (when it has time to start).
fn receiver_case(bits: &[bool], gap_bits: i64, mid_bits: u64, next_kind: u8, distorted: bool) {
    let bt = Duration::from_nanos(62) + Duration::from_picos(500);
    let t0 = Instant::ZERO + Duration::from_micros(3);
    let mut v = BitVec::new();
    for b in bits {
        v.push(*b);
    }
    // A distorted segment (a fault injector's RDIST, 410B §4.1 2H.12) makes its filler
    // schedule an RDIST change of its own.
    let seg = LineSegment {
        distorted,
        ..LineSegment::bits(t0, bt, v, false)
    };
    let end = seg.end().unwrap_or(t0);
    let next_at = Instant::from_picos(
        end.as_picos()
            .saturating_add_signed(gap_bits * bt.as_picos() as i64)
            .max(t0.as_picos() + 1),
    );
    let mid = t0 + bt.saturating_mul(mid_bits);
    let mid = mid.min(next_at - Duration::from_picos(1));
    let next = LineSegment::steady(next_at, bt, signal(next_kind, &[]), false);
    let mut explicit = chip(false);
    let mut implied = chip(false);
    let (bits_only, filler) = LineSegment {
        then_filler: true,
        ..seg.clone()
    }
    .split_filler();
    explicit.line_input(bits_only);
    if let Some(f) = filler.filter(|f| f.start < next_at) {
        explicit.line_input(f);
    }
    implied.line_input(LineSegment {
        then_filler: true,
        ..seg
    });
    for c in [&mut explicit, &mut implied] {
        c.advance_to(mid);
    }
    assert_eq!(state(&mut explicit), state(&mut implied), "at {mid:?}");
    if gap_bits > 0 {
        // Both know of the filler: the same is scheduled (the output the test does not
        // take left out). Otherwise the implied one still counts on it until `next`.
        assert_eq!(
            explicit.next_internal_event_at(),
            implied.next_internal_event_at(),
            "at {mid:?}"
        );
    }
    explicit.line_input(next.clone());
    implied.line_input(next);
    assert_eq!(
        explicit.next_internal_event_at(),
        implied.next_internal_event_at(),
        "after the input"
    );
    // Along the way too: what the filler scheduled and the next segment took back (or
    // not) shows between them and the next FIBBR rise.
    let until = next_at + Duration::from_micros(10);
    let mut checks: Vec<Instant> = [1u64, 8, 33, 40]
        .iter()
        .map(|k| end + bt.saturating_mul(*k))
        .chain([next_at, until])
        .filter(|t| *t >= next_at)
        .collect();
    checks.sort();
    for t in checks {
        for c in [&mut explicit, &mut implied] {
            c.advance_to(t);
        }
        assert_eq!(state(&mut explicit), state(&mut implied), "at {t:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(300)))]
    // 410B §4.1 2H.13 FIBBR: bits without edges for longer than FIBBR_BIT_TIMES raise FIBBR
    // before their filler starts; a segment cutting the filler (or the bits) takes back only
    // what had not happened.
    #[test]
    fn a_receiver_takes_an_implied_filler_as_the_explicit_one(
        bits in proptest::collection::vec(prop_oneof![3 => Just(true), 1 => any::<bool>()], 1..120),
        gap_bits in -20i64..20,
        mid_bits in 0u64..200,
        next_kind in 0u8..3,
        distorted in any::<bool>(),
    ) {
        receiver_case(&bits, gap_bits, mid_bits, next_kind, distorted);
    }
}

#[test]
fn an_edgeless_tail_raises_fibbr_with_or_without_the_filler() {
    // 100 bit times of light, the FIBBR deadline passes inside them; the next segment at
    // the bits' end, after the receiver has passed the deadline.
    receiver_case(&[true; 100], 0, 90, 1, false);
    receiver_case(&[true; 100], -10, 80, 0, false);
    receiver_case(&[true; 100], 5, 95, 2, false);
    // The next segment keeps the light on (no edge of its own): the filler's FIBBR fall,
    // taken back, must not happen.
    receiver_case(&[true; 100], 0, 90, 2, false);
    // Distorted: the filler's RDIST change, taken back (410B §4.1 2H.12).
    receiver_case(&[true; 100], 0, 90, 2, true);
    receiver_case(&[true, false, true, true], -2, 1, 0, true);
}

/// The segments a REPON sender releases for `steps`, with its forwarded copies released or
/// not (`Chip::set_forward_output`), and the starts of those copies; `poltxd`: 410B §4.1
/// 1H.9 POLTXD set, POLRXD not (the repeater inverts the light of what it forwards).
fn released(steps: &[Step], forward: bool, poltxd: bool) -> (Vec<LineSegment>, Vec<Instant>) {
    let mut sender = chip(true);
    if poltxd {
        sender.write_register(1, ENTSBAUD | REPON | POLTXD);
    }
    sender.set_forward_output(forward);
    let bt = Duration::from_nanos(62) + Duration::from_picos(500);
    let latency = bt.saturating_mul(sercon_model::serial_port::REPEATER_LATENCY_BITS);
    let (mut t_send, mut out, mut copies) = (
        Instant::ZERO + Duration::from_micros(2),
        Vec::new(),
        Vec::new(),
    );
    let mut t_in = t_send;
    for s in steps {
        match s {
            Step::Send { gap, bytes } => {
                let at = t_send.max(sender.now()) + bt.saturating_mul(*gap);
                sender.advance_to(at);
                sender.take_line_output(&mut out);
                if let Some(end) = sender.transmit_telegram(at, bytes) {
                    t_send = end;
                }
            }
            Step::Input { gap, kind, bits } => {
                let at = t_in.max(sender.now()) + bt.saturating_mul(*gap);
                sender.advance_to(at);
                sender.take_line_output(&mut out);
                let seg = LineSegment {
                    signal: signal(*kind, bits),
                    ..LineSegment::steady(at, bt, LineSignal::Filler, false)
                };
                t_in = seg.end().unwrap_or(at);
                copies.push(at + latency);
                sender.line_input(seg);
            }
            Step::Extra { .. } => {}
        }
    }
    sender.advance_to(t_send.max(t_in).max(sender.now()) + Duration::from_micros(20));
    sender.take_line_output(&mut out);
    (out, copies)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(200)))]
    // 410B §1 "The slaves regenerate and repeat their received data or send their own
    // telegrams": without its forwarded copies a repeater releases exactly the rest of what
    // it releases with them (own telegrams, what resumes after one), at the same levels.
    #[test]
    fn without_forwarded_copies_a_repeater_releases_the_rest_unchanged(
        steps in proptest::collection::vec(step(), 1..30),
        poltxd in any::<bool>(),
    ) {
        let (with, copies) = released(&steps, true, poltxd);
        let (without, _) = released(&steps, false, poltxd);
        // A copy starts a latency after its input and has no hint (the inputs have none; own
        // telegrams have theirs).
        let rest: Vec<&LineSegment> = with
            .iter()
            .filter(|s| !(copies.contains(&s.start) && s.hint.is_none()))
            .collect();
        let without: Vec<&LineSegment> = without.iter().collect();
        prop_assert_eq!(rest, without);
    }
}
