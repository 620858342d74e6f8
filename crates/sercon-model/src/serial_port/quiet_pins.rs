//! IDLE and REACTN level changes while neither pin is traced (410B §2 IDLE, REACTN; §4.1
//! 3H.14–15): kept in the order they were scheduled, not in time order, and read only when a
//! level is asked for (spec-notes "Quiet pins"). Two changes per telegram, and mostly nobody
//! asks: appending them costs less than keeping them sorted and applying them one by one.

use sercos_wire::time::Instant;

use super::line_events::Change;

/// The shortest list that is trimmed (a telegram schedules two changes; a fold costs about
/// the same at any length, so a longer list folds less often: 16 → 64 saved ≈ 270
/// instructions per ring-8 cycle, 256 cost more on ring-254).
const MIN_TRIM_LEN: usize = 64;

/// Which pin a level change is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PinLine {
    /// IDLE (410B §2).
    Idle,
    /// REACTN (410B §2).
    Reactn,
}

impl PinLine {
    /// The level `change` sets on this pin, if it is a change of this pin.
    fn level(self, change: Change) -> Option<bool> {
        match (self, change) {
            (PinLine::Idle, Change::Idle(l)) | (PinLine::Reactn, Change::Reactn(l)) => Some(l),
            _ => None,
        }
    }
}

/// Quiet IDLE / REACTN changes. The changes up to `applied` (the instant the port has applied
/// its pin levels to) count, the later ones wait; the levels before every change kept are
/// the caller's (`base`, `levels`).
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct QuietPins {
    /// The changes in the order they were scheduled.
    changes: Vec<(Instant, Change)>,
    /// Length at which `changes` is trimmed next.
    trim_len: usize,
    /// The instant of the last IDLE and the last REACTN change put in (`Instant` zero, which
    /// no change is before, for none): while `unsorted` is false, each pin's latest change
    /// in `changes`, or not after the applied instant.
    last: (Instant, Instant),
    /// Some pin's changes may not be in time order (else the latest one at or before an
    /// instant is the last such one in the list).
    unsorted: bool,
    /// The instant the pin levels are applied to.
    applied: Instant,
    /// The latest own telegram's IDLE interval (410B §2 IDLE: "When transmitting own data
    /// IDLE is 0"): 0 from the first instant, 1 again from the second, both no earlier than
    /// the applied instant when kept. It stands for the two changes a time-ordered queue
    /// would hold, and comes after every IDLE change in `changes`, in time and as scheduled
    /// (spec-notes "Own IDLE interval").
    own: Option<(Instant, Instant)>,
    /// The end of the own interval `own` replaced, which was at or before the applied
    /// instant then: IDLE is 1 before `own` whatever `changes` and the base say.
    own_ended: Option<Instant>,
}

/// Notes a change of its pin at `at` after the ones noted in `last` (IDLE, REACTN); returns
/// whether it comes before the last one of its pin.
fn follows_out_of_order(last: &mut (Instant, Instant), at: Instant, change: Change) -> bool {
    let last = if matches!(change, Change::Idle(_)) {
        &mut last.0
    } else {
        &mut last.1
    };
    let before = at < *last;
    *last = at;
    before
}

impl QuietPins {
    /// Keeps a change. One scheduled before the applied instant counts from that instant,
    /// after the changes applied (as a time-ordered queue applies it with its next
    /// application, after those it applied before).
    pub(crate) fn push(&mut self, at: Instant, change: Change) {
        if matches!(change, Change::Idle(_)) {
            // After the own interval as scheduled.
            self.flush_own();
        }
        let at = at.max(self.applied);
        self.keep(at, change);
    }

    /// A received telegram's REACTN pulse (410B §2 REACTN: low from `low` while the
    /// telegram is received, high again from `end`): the two changes [`QuietPins::push`]
    /// keeps for `(low, Reactn(false))` and then `(end, Reactn(true))`, appended in one go
    /// when `low` ≤ `end` (every pulse the receiver schedules: it falls with the opening
    /// flag's end or the frame's, whichever comes first); debug builds compare with the
    /// two pushes.
    #[inline(always)]
    pub(crate) fn push_reactn_pulse(&mut self, low: Instant, end: Instant) {
        #[cfg(debug_assertions)]
        let general = {
            let mut general = self.clone();
            general.push(low, Change::Reactn(false));
            general.push(end, Change::Reactn(true));
            general
        };
        if low <= end {
            // Both taken from the applied instant on, in order: only the fall can come
            // before REACTN's last change kept.
            let (low, end) = (low.max(self.applied), end.max(self.applied));
            self.unsorted |= low < self.last.1;
            self.last.1 = end;
            self.changes.push((low, Change::Reactn(false)));
            self.changes.push((end, Change::Reactn(true)));
        } else {
            self.push(low, Change::Reactn(false));
            self.push(end, Change::Reactn(true));
        }
        #[cfg(debug_assertions)]
        debug_assert!(
            *self == general,
            "a REACTN pulse appended in one go differs from its two pushes"
        );
    }

    /// Appends a change as it is.
    fn keep(&mut self, at: Instant, change: Change) {
        self.unsorted |= follows_out_of_order(&mut self.last, at, change);
        self.changes.push((at, change));
    }

    /// Keeps an own telegram's IDLE changes (0 at `start`, 1 at `end`; 410B §2 IDLE) as
    /// the interval `own` when they come after every IDLE change kept (the usual case: the
    /// transmitter places a telegram after the one it sends), else as the two changes.
    pub(crate) fn push_own(&mut self, start: Instant, end: Instant) {
        let (start, end) = (start.max(self.applied), end.max(self.applied));
        if let Some((_, e)) = self.own {
            if e <= self.applied {
                // Its end counts already: IDLE is 1 until the new one starts.
                self.own = None;
                self.own_ended = Some(e);
            } else {
                self.flush_own();
            }
        }
        if self.unsorted || start < self.last.0 || end < start {
            // Not after every IDLE change kept (`last.0` is the latest while the list is in
            // time order): as changes.
            self.flush_own();
            self.keep(start, Change::Idle(false));
            self.keep(end, Change::Idle(true));
            return;
        }
        self.own = Some((start, end));
    }

    /// Puts the own interval (and the end it replaced) into `changes` as the changes it
    /// stands for.
    fn flush_own(&mut self) {
        if let Some(e) = self.own_ended.take() {
            self.keep(e, Change::Idle(true));
        }
        if let Some((s, e)) = self.own.take() {
            self.keep(s, Change::Idle(false));
            self.keep(e, Change::Idle(true));
        }
    }

    /// The level of `pin`: its change latest in time at or before the applied instant (of
    /// several at one instant, the last scheduled, as a time-ordered queue would apply
    /// them), else `base`.
    pub(crate) fn level(&self, pin: PinLine, base: bool) -> bool {
        let upto = self.applied;
        if pin == PinLine::Idle {
            // The own interval is the latest IDLE change in time and as scheduled.
            if let Some((s, e)) = self.own
                && s <= upto
            {
                return upto >= e;
            }
            if self.own_ended.is_some() {
                return true;
            }
        }
        if !self.unsorted {
            // Each pin's changes in time order: its latest one at or before `upto` is the
            // last such one (of several at one instant, the last scheduled).
            return self
                .changes
                .iter()
                .rev()
                .find_map(|&(at, change)| pin.level(change).filter(|_| at <= upto))
                .unwrap_or(base);
        }
        let mut latest: Option<(Instant, bool)> = None;
        for &(at, change) in &self.changes {
            if let Some(level) = pin.level(change)
                && at <= upto
                && latest.is_none_or(|(t, _)| at >= t)
            {
                latest = Some((at, level));
            }
        }
        latest.map_or(base, |(_, level)| level)
    }

    /// The changes up to `t` count from now on; returns whether the list has grown long
    /// enough to be folded (`apply` does).
    #[inline]
    pub(crate) fn apply_folds(&mut self, t: Instant) -> bool {
        self.applied = self.applied.max(t);
        self.folds()
    }

    /// Whether the list has grown long enough to be folded at its next application.
    #[inline]
    pub(crate) fn folds(&self) -> bool {
        self.changes.len() >= self.trim_len.max(MIN_TRIM_LEN)
    }

    /// The changes up to `t` count from now on; once the list has grown long, those are
    /// folded into `levels` (IDLE, REACTN before every change kept) and dropped.
    pub(crate) fn apply(&mut self, t: Instant, levels: &mut (bool, bool)) {
        if !self.apply_folds(t) {
            return;
        }
        self.fold(levels);
        self.trim_len = 2 * self.changes.len();
    }

    /// Folds the changes up to the applied instant into `levels` and drops them.
    fn fold(&mut self, levels: &mut (bool, bool)) {
        let upto = self.applied;
        levels.0 = self.level(PinLine::Idle, levels.0);
        levels.1 = self.level(PinLine::Reactn, levels.1);
        if !self.unsorted && self.last.0 <= upto && self.last.1 <= upto {
            // Every change read (the usual case): each pin's last one is its latest.
            self.changes.clear();
        } else {
            self.changes.retain(|(at, _)| *at > upto);
        }
        // Read into `levels`: what is left of the own interval comes after them.
        self.own_ended = None;
        if self.own.is_some_and(|(_, e)| e <= upto) {
            self.own = None;
        }
        if self.unsorted {
            // Whether what is left is in time order again, pin by pin.
            let mut last = (Instant::default(), Instant::default());
            let mut unsorted = false;
            for &(at, change) in &self.changes {
                unsorted |= follows_out_of_order(&mut last, at, change);
            }
            self.unsorted = unsorted;
            self.last = last;
        }
    }

    /// Drops the receiver's changes at or after `t` that are not applied yet (a collision
    /// cut the signal they came from; a time-ordered queue no longer holds applied ones).
    pub(crate) fn cancel_receive_from(&mut self, t: Instant) {
        let applied = self.applied;
        self.changes
            .retain(|(at, c)| *at < t || *at <= applied || !c.is_receive());
    }

    /// Folds the applied changes into `levels` and hands over the rest, in the order they
    /// were scheduled (for a time-ordered queue, when a pin gets traced).
    pub(crate) fn take_pending(
        &mut self,
        levels: &mut (bool, bool),
    ) -> std::vec::IntoIter<(Instant, Change)> {
        self.fold(levels);
        self.flush_own();
        self.last = (Instant::default(), Instant::default());
        self.unsorted = false;
        std::mem::take(&mut self.changes).into_iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn at(ns: u64) -> Instant {
        Instant::from_picos(ns * 1000)
    }

    proptest! {
        /// 410B §2 REACTN: a pulse appended in one go (`push_reactn_pulse`) leaves the quiet
        /// changes exactly as its two pushes do, whatever was kept before (REACTN changes
        /// out of time order, own IDLE intervals, changes applied and folded) and whether
        /// the pulse falls before its rise or not.
        #[test]
        fn a_reactn_pulse_is_its_two_pushes(
            steps in prop::collection::vec((0u8..6, 0u64..200, 0u64..200), 1..60),
        ) {
            let (mut pulsed, mut pushed) = (QuietPins::default(), QuietPins::default());
            let (mut lp, mut lq) = ((true, true), (true, true));
            for (kind, a, b) in steps {
                match kind {
                    0 | 1 => {
                        // The receiver's pulse: it falls no later than it rises.
                        let (low, end) = (at(a.min(b)), at(a.max(b)));
                        pulsed.push_reactn_pulse(low, end);
                        pushed.push(low, Change::Reactn(false));
                        pushed.push(end, Change::Reactn(true));
                    }
                    2 => {
                        // Any other order takes the two pushes.
                        pulsed.push_reactn_pulse(at(a), at(b));
                        pushed.push(at(a), Change::Reactn(false));
                        pushed.push(at(b), Change::Reactn(true));
                    }
                    3 => {
                        let change = if b % 2 == 0 { Change::Reactn(b % 4 == 0) } else { Change::Idle(b % 3 == 0) };
                        pulsed.push(at(a), change);
                        pushed.push(at(a), change);
                    }
                    4 => {
                        pulsed.push_own(at(a), at(a + b));
                        pushed.push_own(at(a), at(a + b));
                    }
                    _ => {
                        pulsed.apply(at(a), &mut lp);
                        pushed.apply(at(a), &mut lq);
                    }
                }
                prop_assert_eq!(&pulsed, &pushed);
                prop_assert_eq!(lp, lq);
                prop_assert_eq!(
                    pulsed.level(PinLine::Reactn, lp.1),
                    pushed.level(PinLine::Reactn, lq.1)
                );
            }
        }
    }
}
