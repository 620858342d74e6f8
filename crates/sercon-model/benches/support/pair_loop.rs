//! Two chips back to back (chip 0's output to chip 1's input and back, one fibre delay each
//! way), advanced by a conservative event loop with a horizon per chip. Used by the
//! `ring_pair` bench and checked against a stepped run by `tests/pair_horizons.rs`.

use sercon_model::Chip;
use sercon_model::serial_port::LineSegment;
use sercos_wire::time::{Duration, Instant};

/// Two chips in a ring, advanced by a conservative event loop with a horizon per chip.
///
/// Nothing chip `j` has not sent yet starts before `L_j = min(e_j, e_i + d)`, where `e` is
/// [`Chip::next_event_at`] (its own next event or queued output) and `e_i + d` the earliest
/// instant an output of the other chip `i` reaches `j` and may make it send (a repeater, or a
/// telegram processor that reacts to a frame). So every round advances chip `i` to just
/// before `L_j + d`, the first instant anything from `j` can arrive, and carries the released
/// output segments over the fibre. Unlike one horizon for both chips (the minimum of both
/// `e + d`), a chip's own events bound it only two fibre delays ahead.
#[derive(Clone)]
pub struct Pair {
    /// The two chips: 0 sends to 1, 1 sends to 0.
    pub chips: [Chip; 2],
    /// Fibre delay, each way (must be more than 0).
    pub delay: Duration,
    /// The instant both chips have reached.
    pub now: Instant,
    /// Every output segment handed over, with the number of the chip that sent it, when
    /// `Some` (for tests).
    pub log: Option<Vec<(usize, LineSegment)>>,
    buf: Vec<LineSegment>,
}

impl Pair {
    /// `chips` wired back to back at time 0 with `delay` of fibre each way.
    pub fn new(chips: [Chip; 2], delay: Duration) -> Pair {
        Pair {
            chips,
            delay,
            now: Instant::ZERO,
            log: None,
            buf: Vec::new(),
        }
    }

    /// Runs both chips to `until`.
    pub fn run_to(&mut self, until: Instant) {
        let d = self.delay;
        // Just before `at`: the horizon is exclusive of the first possible arrival.
        let before = |at: Instant| Instant::from_picos(at.as_picos().saturating_sub(1));
        while self.chips.iter().any(|c| c.now() < until) {
            let e = [self.chips[0].next_event_at(), self.chips[1].next_event_at()];
            // The earliest start of anything chip `j` sends from now on.
            let sends = |j: usize| {
                let own = e[j];
                let reply = e[1 - j].map(|t| t.saturating_add(d));
                match (own, reply) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                }
            };
            let horizon = [0, 1]
                .map(|i| sends(1 - i).map_or(until, |l| before(l.saturating_add(d)).min(until)));
            // Whether chip 1 was handed segments in this round (then its `e` is stale).
            let mut fed = false;
            for (i, h) in horizon.into_iter().enumerate() {
                let c = &mut self.chips[i];
                // Nothing of this chip is due up to `h` (no event, no output to release): the
                // advance would only move its time, which a later one does as well (an
                // advance with nothing due changes nothing else; `Chip::next_event_at`), so
                // it is left out. Both chips cannot skip in one round: that needs
                // `e_1 + d ≤ e_0` and `e_0 + d ≤ e_1`. The last advance, to `until`, is kept.
                let idle = h < until && !(i == 1 && fed) && e[i].is_none_or(|n| n > h);
                if idle {
                    continue;
                }
                c.advance_to(h);
                c.take_line_output(&mut self.buf);
                let to = &mut self.chips[1 - i];
                fed |= !self.buf.is_empty();
                for seg in self.buf.drain(..) {
                    if let Some(log) = self.log.as_mut() {
                        log.push((i, seg.clone()));
                    }
                    to.line_input(seg.delayed(d));
                }
            }
        }
        self.now = until;
    }
}

/// Runs `chips` back to back to `until` in steps of half the fibre delay, so that every
/// segment reaches the other chip before its time passes the segment's start (the line
/// interface's contract, `Chip::line_input`): the plain reference the event loop above is
/// checked against. `before(i, chip)` is asked right before chip `i` is advanced; every
/// segment chip `i` then releases goes to `released(i, &answer, segment)` and on to the other
/// chip.
// The bench does not use it.
#[allow(dead_code)]
pub fn stepped<T>(
    chips: &mut [Chip; 2],
    delay: Duration,
    until: Instant,
    mut before: impl FnMut(usize, &Chip) -> T,
    mut released: impl FnMut(usize, &T, &LineSegment),
) {
    let step = Duration::from_picos((delay.as_picos() / 2).max(1));
    let mut now = Instant::ZERO;
    let mut buf = Vec::new();
    while now < until {
        now = (now + step).min(until);
        for i in 0..2 {
            let answer = before(i, &chips[i]);
            chips[i].advance_to(now);
            chips[i].take_line_output(&mut buf);
            for seg in buf.drain(..) {
                released(i, &answer, &seg);
                chips[1 - i].line_input(seg.delayed(delay));
            }
        }
    }
}
