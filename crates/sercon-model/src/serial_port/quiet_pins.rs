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
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct QuietPins {
    /// The changes in the order they were scheduled.
    changes: Vec<(Instant, Change)>,
    /// Length at which `changes` is trimmed next (at least [`MIN_TRIM_LEN`]).
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
    /// The own interval before `own`, not over at the applied instant when `own` came (a
    /// master queues its MDT while its MST is sent): ending no later than `own` starts,
    /// after every IDLE change in `changes`; `None` while `own` is.
    own_before: Option<(Instant, Instant)>,
    /// The end of the own interval `own` (and `own_before`) replaced, which was at or
    /// before the applied instant then: IDLE is 1 before them whatever `changes` and the
    /// base say.
    own_ended: Option<Instant>,
    /// The latest received telegram's REACTN pulse (410B §2 REACTN: low while a telegram is
    /// received): 0 from the first instant, 1 again from the second, both no earlier than
    /// the applied instant when kept. It stands for the two changes a time-ordered queue
    /// would hold, and comes after every REACTN change in `changes` and `pulses`, in time
    /// and as scheduled (spec-notes "Received REACTN pulses").
    pulse: Option<(Instant, Instant)>,
    /// The pulses before `pulse` that had not ended at the applied instant when it came
    /// (telegrams received in a batch, a master's ATs), in time order, each starting no
    /// earlier than the one before ends, after every REACTN change in `changes`; empty
    /// while `pulse` is `None`.
    pulses: Vec<(Instant, Instant)>,
    /// The end of the pulses `pulse` and `pulses` replaced, which were over by the
    /// applied instant then: REACTN is 1 before them whatever `changes` and the base say.
    pulse_ended: Option<Instant>,
}

impl Default for QuietPins {
    fn default() -> Self {
        QuietPins {
            changes: Vec::new(),
            trim_len: MIN_TRIM_LEN,
            last: (Instant::default(), Instant::default()),
            unsorted: false,
            applied: Instant::default(),
            own: None,
            own_before: None,
            own_ended: None,
            pulse: None,
            pulses: Vec::new(),
            pulse_ended: None,
        }
    }
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
        } else {
            // After the received pulse as scheduled.
            self.flush_pulses();
        }
        let at = at.max(self.applied);
        self.keep(at, change);
    }

    /// A received telegram's REACTN pulse (410B §2 REACTN: low from `low` while the
    /// telegram is received, high again from `end`): the two changes [`QuietPins::push`]
    /// keeps for `(low, Reactn(false))` and then `(end, Reactn(true))`. When `low` ≤ `end`
    /// (every pulse the receiver schedules: it falls with the opening flag's end or the
    /// frame's, whichever comes first) it is kept as the pulse `pulse` when it comes after
    /// every REACTN change kept (telegrams are received one after the other), else appended
    /// in one go ([`QuietPins::push_reactn_pulse_kept`], else
    /// [`QuietPins::push_reactn_pulse_rest`]).
    #[cfg(test)]
    pub(crate) fn push_reactn_pulse(&mut self, low: Instant, end: Instant) {
        if !self.push_reactn_pulse_kept(low, end) {
            self.push_reactn_pulse_rest(low, end);
        }
    }

    /// [`QuietPins::push_reactn_pulse`] when the new pulse comes after the one kept, which is
    /// over by the applied instant with none before it (a slave's usual case) or not over
    /// yet (telegrams received in a batch): kept in place, inline. Returns whether it was;
    /// `false` leaves everything as it was. No pulse is kept while the pins are loud
    /// (`take_pending` put it into the list), so it is `false` then. Debug builds compare
    /// the levels with the two pushes.
    #[inline(always)]
    pub(crate) fn push_reactn_pulse_kept(&mut self, low: Instant, end: Instant) -> bool {
        #[cfg(debug_assertions)]
        let general = self.pushed_pair(low, end, Change::Reactn);
        let applied = self.applied;
        if let Some((l, e)) = self.pulse
            && applied <= low
            && low <= end
        {
            if e <= applied {
                if self.pulses.is_empty() {
                    // REACTN is 1 from the end of the pulse kept until the new one falls.
                    self.pulse_ended = Some(e);
                    self.pulse = Some((low, end));
                    #[cfg(debug_assertions)]
                    self.check_levels_against(&general, [low, end]);
                    return true;
                }
            } else if low >= e {
                // After the one kept, which has not ended (telegrams received in a batch,
                // a master's ATs).
                self.pulses.push((l, e));
                self.pulse = Some((low, end));
                #[cfg(debug_assertions)]
                self.check_levels_against(&general, [low, end]);
                return true;
            }
        }
        false
    }

    /// Debug builds: a copy with a pulse's or an own interval's two changes (`pin` 0 from
    /// `low`, 1 from `end`) pushed one by one, as the general path schedules them.
    #[cfg(debug_assertions)]
    fn pushed_pair(&self, low: Instant, end: Instant, pin: fn(bool) -> Change) -> QuietPins {
        let mut general = self.clone();
        general.push(low, pin(false));
        general.push(end, pin(true));
        general
    }

    /// [`QuietPins::push_reactn_pulse`] out of line, in every case; debug builds compare
    /// the levels with the two pushes.
    #[cold]
    #[inline(never)]
    pub(crate) fn push_reactn_pulse_rest(&mut self, low: Instant, end: Instant) {
        #[cfg(debug_assertions)]
        let general = self.pushed_pair(low, end, Change::Reactn);
        self.push_reactn_pulse_unchecked(low, end);
        #[cfg(debug_assertions)]
        self.check_levels_against(&general, [low, end]);
    }

    /// [`QuietPins::push_reactn_pulse_rest`] without its check.
    fn push_reactn_pulse_unchecked(&mut self, low: Instant, end: Instant) {
        if low > end {
            self.push(low, Change::Reactn(false));
            self.push(end, Change::Reactn(true));
            return;
        }
        // Both taken from the applied instant on, in order.
        let (low, end) = (low.max(self.applied), end.max(self.applied));
        if let Some((l, e)) = self.pulse {
            if e <= self.applied {
                // The pulses kept are over by the applied instant: REACTN is 1 until the
                // new one falls, at or after that instant.
                self.pulse_ended = Some(e);
                self.pulses.clear();
                self.pulse = Some((low, end));
                return;
            }
            if low >= e {
                // After the one kept, which has not ended (telegrams received in a batch).
                self.pulses.push((l, e));
                self.pulse = Some((low, end));
                return;
            }
            self.flush_pulses();
        }
        if self.unsorted || low < self.last.1 {
            // Not after every REACTN change kept (`last.1` is the latest while the list is
            // in time order): appended, only the fall can come before REACTN's last change.
            self.unsorted |= low < self.last.1;
            self.last.1 = end;
            self.changes.push((low, Change::Reactn(false)));
            self.changes.push((end, Change::Reactn(true)));
            return;
        }
        self.pulse = Some((low, end));
    }

    /// Debug builds: the levels of both pins read at the applied instant and at each of
    /// `later` (those at or after it) are the ones `general` (the same changes kept as
    /// pushed one by one) reads, from either base level.
    #[cfg(debug_assertions)]
    fn check_levels_against(&self, general: &QuietPins, later: [Instant; 2]) {
        for at in std::iter::once(self.applied).chain(later) {
            if at < self.applied {
                continue;
            }
            let (mut mine, mut theirs) = (self.clone(), general.clone());
            mine.applied = at;
            theirs.applied = at;
            for base in [false, true] {
                for pin in [PinLine::Idle, PinLine::Reactn] {
                    debug_assert_eq!(
                        mine.level(pin, base),
                        theirs.level(pin, base),
                        "a REACTN pulse kept differs from its two pushes ({pin:?} at {at:?})"
                    );
                }
            }
        }
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
        if self.push_own_kept(start, end) {
            return;
        }
        let (start, end) = (start.max(self.applied), end.max(self.applied));
        if let Some((_, e)) = self.own {
            if e <= self.applied {
                // Its end (and the one's before it) counts already: IDLE is 1 until the new
                // one starts.
                self.own = None;
                self.own_before = None;
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

    /// [`QuietPins::push_own`] when the new interval starts no earlier than the applied
    /// instant and than the interval kept ends (the usual case), inline: when that one has
    /// ended by the applied instant, the new one replaces it (and the one before it); when
    /// not (a master's MDT queued while its MST is sent), it moves to `own_before`, where
    /// the one before it has ended. Returns whether it did; `false` leaves everything as it
    /// was. No interval is kept while the pins are loud (`take_pending` put it into the
    /// list), so it is `false` then. Debug builds compare the levels with the two pushes.
    #[inline(always)]
    pub(crate) fn push_own_kept(&mut self, start: Instant, end: Instant) -> bool {
        #[cfg(debug_assertions)]
        let general = self.pushed_pair(start, end, Change::Idle);
        let applied = self.applied;
        if let Some((s, e)) = self.own
            && applied <= start
            && start <= end
        {
            if e <= applied {
                // After every IDLE change kept, as the ones it replaces: IDLE is 1 until it
                // starts.
                self.own_ended = Some(e);
                self.own_before = None;
                self.own = Some((start, end));
                #[cfg(debug_assertions)]
                self.check_levels_against(&general, [start, end]);
                return true;
            }
            if e <= start && self.own_before.is_none_or(|(_, b)| b <= applied) {
                // After the one kept, which has not ended; the one before that has (IDLE
                // is 1 from its end until the one kept starts).
                if let Some((_, b)) = self.own_before {
                    self.own_ended = Some(b);
                }
                self.own_before = Some((s, e));
                self.own = Some((start, end));
                #[cfg(debug_assertions)]
                self.check_levels_against(&general, [start, end]);
                return true;
            }
        }
        false
    }

    /// Puts the own interval (and the end it replaced) into `changes` as the changes it
    /// stands for.
    fn flush_own(&mut self) {
        if let Some(e) = self.own_ended.take() {
            self.keep(e, Change::Idle(true));
        }
        if let Some((s, e)) = self.own_before.take() {
            self.keep(s, Change::Idle(false));
            self.keep(e, Change::Idle(true));
        }
        if let Some((s, e)) = self.own.take() {
            self.keep(s, Change::Idle(false));
            self.keep(e, Change::Idle(true));
        }
    }

    /// Puts the received pulses (and the end they replaced) into `changes` as the changes
    /// they stand for.
    fn flush_pulses(&mut self) {
        if let Some(e) = self.pulse_ended.take() {
            self.keep(e, Change::Reactn(true));
        }
        let pulses = std::mem::take(&mut self.pulses);
        for (l, e) in pulses.into_iter().chain(self.pulse.take()) {
            self.keep(l, Change::Reactn(false));
            self.keep(e, Change::Reactn(true));
        }
    }

    /// The level of `pin`: its change latest in time at or before the applied instant (of
    /// several at one instant, the last scheduled, as a time-ordered queue would apply
    /// them), else `base`.
    pub(crate) fn level(&self, pin: PinLine, base: bool) -> bool {
        let upto = self.applied;
        // The own interval is the latest IDLE change in time and as scheduled, the received
        // pulses the latest REACTN changes (the last one started rules).
        let (kept, ended) = match pin {
            PinLine::Idle => (
                self.own
                    .filter(|(s, _)| *s <= upto)
                    .or(self.own_before.filter(|(s, _)| *s <= upto)),
                self.own_ended.is_some(),
            ),
            PinLine::Reactn => (
                self.pulse
                    .filter(|(s, _)| *s <= upto)
                    .or_else(|| self.pulses.iter().rev().find(|(s, _)| *s <= upto).copied()),
                self.pulse_ended.is_some(),
            ),
        };
        if let Some((s, e)) = kept
            && s <= upto
        {
            return upto >= e;
        }
        if ended {
            return true;
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

    /// The changes up to `t`, at or after the applied instant (the chip's time, which only
    /// moves on), count from now on; the list is not folded.
    #[inline]
    pub(crate) fn apply_to(&mut self, t: Instant) {
        debug_assert!(t >= self.applied, "quiet pins applied back in time");
        self.applied = t;
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
        debug_assert!(self.trim_len >= MIN_TRIM_LEN);
        self.changes.len() >= self.trim_len
    }

    /// The changes up to `t` count from now on; once the list has grown long, those are
    /// folded into `levels` (IDLE, REACTN before every change kept) and dropped.
    pub(crate) fn apply(&mut self, t: Instant, levels: &mut (bool, bool)) {
        if !self.apply_folds(t) {
            return;
        }
        self.fold(levels);
        self.trim_len = (2 * self.changes.len()).max(MIN_TRIM_LEN);
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
        // Read into `levels`: what is left of the own interval and the received pulse comes
        // after them.
        self.own_ended = None;
        if self.own.is_some_and(|(_, e)| e <= upto) {
            // Both kept are over.
            self.own = None;
            self.own_before = None;
        } else if self.own_before.is_some_and(|(_, e)| e <= upto) {
            self.own_before = None;
        }
        self.pulse_ended = None;
        if self.pulse.is_some_and(|(_, e)| e <= upto) {
            // Every pulse kept is over.
            self.pulse = None;
            self.pulses.clear();
        } else {
            self.pulses.retain(|(_, e)| *e > upto);
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
        self.flush_pulses();
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
        self.flush_pulses();
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

    /// The pulses and single REACTN changes of `steps` kept as `push_reactn_pulse` keeps
    /// them and as their changes pushed one by one, with the levels applied up to `applied`.
    fn pulsed_and_pushed(steps: &[(u64, u64)], applied: u64) -> (QuietPins, QuietPins) {
        let (mut pulsed, mut pushed) = (QuietPins::default(), QuietPins::default());
        let mut levels = (true, true);
        for &(low, end) in steps {
            pulsed.push_reactn_pulse(at(low), at(end));
            pushed.push(at(low), Change::Reactn(false));
            pushed.push(at(end), Change::Reactn(true));
        }
        pulsed.apply(at(applied), &mut levels);
        pushed.apply(at(applied), &mut levels);
        (pulsed, pushed)
    }

    /// 410B §2 REACTN: a pulse that falls before the applied instant counts from that
    /// instant; kept and then put into the list with the one before it (by a single REACTN
    /// change), REACTN is still 0 until it rises.
    #[test]
    fn a_late_pulse_counts_from_the_applied_instant_in_the_list_too() {
        let (mut pulsed, mut pushed) = pulsed_and_pushed(&[(1, 3)], 10);
        // Falls at 2, before 10 and before the last one's rise at 3.
        pulsed.push_reactn_pulse(at(2), at(20));
        pushed.push(at(2), Change::Reactn(false));
        pushed.push(at(20), Change::Reactn(true));
        pulsed.push(at(50), Change::Reactn(true));
        pushed.push(at(50), Change::Reactn(true));
        assert!(!pushed.level(PinLine::Reactn, true));
        assert!(!pulsed.level(PinLine::Reactn, true));
    }

    /// 410B §2 IDLE: an own interval given with its end before its start (the transmitter
    /// places none so; kept exact) reads as its two changes, IDLE 0 from its start on, also
    /// after an interval that has ended.
    #[test]
    fn an_own_interval_ending_before_it_starts_reads_as_its_two_changes() {
        let (mut kept, mut pushed) = (QuietPins::default(), QuietPins::default());
        let (mut lk, mut lp) = ((true, true), (true, true));
        for (start, end, applied) in [(1, 2, 5), (8, 6, 10)] {
            kept.push_own(at(start), at(end));
            pushed.push(at(start), Change::Idle(false));
            pushed.push(at(end), Change::Idle(true));
            kept.apply(at(applied), &mut lk);
            pushed.apply(at(applied), &mut lp);
        }
        assert!(!pushed.level(PinLine::Idle, lp.0));
        assert!(!kept.level(PinLine::Idle, lk.0));
    }

    /// The pulses kept while one had not ended (a batch) are dropped once the last one is
    /// over and the next comes: the list of pulses does not grow from cycle to cycle.
    #[test]
    fn pulses_over_are_dropped_when_the_next_comes() {
        let (mut pulsed, pushed) = pulsed_and_pushed(&[(10, 12), (13, 15), (16, 18)], 5);
        assert_eq!(
            pulsed.pulses.len(),
            2,
            "a batch of three: two before the last"
        );
        assert_eq!(
            pulsed.level(PinLine::Reactn, true),
            pushed.level(PinLine::Reactn, true)
        );
        let mut levels = (true, true);
        for k in 0..4 {
            pulsed.apply(at(30 + 10 * k), &mut levels);
            pulsed.push_reactn_pulse(at(31 + 10 * k), at(33 + 10 * k));
            assert!(pulsed.pulses.is_empty(), "pulse {k}: the ones over dropped");
        }
    }

    /// 410B §2 IDLE: a master queues its next own telegram while the one before is sent
    /// (its MDT during its MST): the one not over is kept before the new one, not put into
    /// the list, and dropped once over; the levels are those of the changes pushed one by
    /// one at every instant.
    #[test]
    fn an_own_interval_not_over_is_kept_before_the_next() {
        let (mut kept, mut pushed) = (QuietPins::default(), QuietPins::default());
        let (mut lk, mut lp) = ((true, true), (true, true));
        // (start, end, applied before the push): the first two come while nothing has been
        // applied, each later one while the one before is sent (or, at 12, not started yet
        // with the one before it over). The list stays empty, nothing is folded: the levels
        // agree from either base.
        for (k, (start, end, applied)) in [
            (10, 12, 5),
            (13, 15, 5),
            (16, 18, 12),
            (19, 21, 17),
            (30, 32, 25),
        ]
        .into_iter()
        .enumerate()
        {
            kept.apply(at(applied), &mut lk);
            pushed.apply(at(applied), &mut lp);
            kept.push_own(at(start), at(end));
            pushed.push(at(start), Change::Idle(false));
            pushed.push(at(end), Change::Idle(true));
            assert!(kept.changes.is_empty(), "interval {k}: nothing in the list");
            if k == 1 {
                assert!(
                    kept.own_before.is_some(),
                    "the first kept before the second"
                );
            }
            for t in applied..40 {
                let (mut a, mut b) = (kept.clone(), pushed.clone());
                a.applied = at(t);
                b.applied = at(t);
                for base in [false, true] {
                    assert_eq!(
                        a.level(PinLine::Idle, base),
                        b.level(PinLine::Idle, base),
                        "interval {k}, read at {t} from {base}"
                    );
                }
            }
        }
        // Three intervals each queued before the one before ends: the second not over at
        // the third, so the first and second go into the list, and the levels still agree.
        let (mut kept, mut pushed) = (QuietPins::default(), QuietPins::default());
        for (start, end) in [(10, 12), (13, 15), (14, 20), (21, 22)] {
            kept.push_own(at(start), at(end));
            pushed.push(at(start), Change::Idle(false));
            pushed.push(at(end), Change::Idle(true));
        }
        for t in 0..30 {
            let (mut a, mut b) = (kept.clone(), pushed.clone());
            a.applied = at(t);
            b.applied = at(t);
            assert_eq!(
                a.level(PinLine::Idle, true),
                b.level(PinLine::Idle, true),
                "at {t}"
            );
        }
        let mut levels = (true, true);
        kept.apply(at(100), &mut levels);
        kept.fold(&mut levels);
        assert!(
            kept.own.is_none() && kept.own_before.is_none(),
            "both over, dropped"
        );
    }

    proptest! {
        /// 410B §2 IDLE: own intervals kept (`push_own`) give the levels their two pushes
        /// give, whatever was kept before (IDLE changes out of time order, intervals not
        /// over when the next comes, changes applied and folded).
        #[test]
        fn an_own_interval_is_its_two_pushes(
            steps in prop::collection::vec((0u8..5, 0u64..200, 0u64..40), 1..60),
        ) {
            let (mut kept, mut pushed) = (QuietPins::default(), QuietPins::default());
            let (mut lk, mut lp) = ((true, true), (true, true));
            for (kind, a, b) in steps {
                match kind {
                    0 | 1 => {
                        kept.push_own(at(a), at(a + b));
                        pushed.push(at(a), Change::Idle(false));
                        pushed.push(at(a + b), Change::Idle(true));
                    }
                    2 => {
                        let change = Change::Idle(b % 2 == 0);
                        kept.push(at(a), change);
                        pushed.push(at(a), change);
                    }
                    _ => {
                        kept.apply(at(a), &mut lk);
                        pushed.apply(at(a), &mut lp);
                    }
                }
                prop_assert_eq!(
                    kept.level(PinLine::Idle, lk.0),
                    pushed.level(PinLine::Idle, lp.0)
                );
            }
        }
    }

    proptest! {
        /// 410B §2 REACTN: a pulse kept or appended in one go (`push_reactn_pulse`) gives
        /// the levels its two pushes give, whatever was kept before (REACTN changes out of
        /// time order, own IDLE intervals, changes applied and folded, a kept pulse ended
        /// or not at the next one) and whether the pulse falls before its rise or not.
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
                // The pulse kept folds less often: the levels read, not the lists, agree.
                prop_assert_eq!(
                    pulsed.level(PinLine::Idle, lp.0),
                    pushed.level(PinLine::Idle, lq.0)
                );
                prop_assert_eq!(
                    pulsed.level(PinLine::Reactn, lp.1),
                    pushed.level(PinLine::Reactn, lq.1)
                );
            }
        }
    }
}
