//! The serial port's scheduled status changes (pins IDLE, REACTN; status bits FIBBR, RDIST),
//! kept in time order and applied when the chip's time reaches them.
//!
//! Two queues: the status bits (FIBBR, RDIST raise interrupts and drive L_ERRN, so the chip
//! applies them in time order with its other events) and the pin levels (IDLE, REACTN,
//! which nothing else depends on). While one of those pins is traced ("loud") their changes
//! are kept in time order and applied one instant at a time; otherwise ("quiet") they are
//! only appended as they are scheduled and read when a level is asked for
//! ([`LineEvents::quiet_level`]): four of them per telegram, and mostly nobody asks.

use std::collections::VecDeque;

use sercos_wire::time::Instant;

use super::quiet_pins::{PinLine, QuietPins};
use crate::chip::earliest;

/// One scheduled change of a line status.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Change {
    /// IDLE pin level (410B §2: low while the node sends its own data).
    Idle(bool),
    /// REACTN pin level (410B §2: low while a telegram is being received).
    Reactn(bool),
    /// FIBBR status (410B §4.1 2H.13: no edges on the receive data).
    Fibbr(bool),
    /// RDIST status (410B §4.1 2H.12: receive data over the distortion limit).
    Rdist(bool),
}

impl Change {
    /// Whether this change only sets the level of pin IDLE or REACTN.
    pub(crate) fn is_pin_level(self) -> bool {
        matches!(self, Change::Idle(_) | Change::Reactn(_))
    }

    /// Whether the receiver scheduled this change (and a collision may cancel it).
    pub(crate) fn is_receive(self) -> bool {
        !matches!(self, Change::Idle(_))
    }
}

/// Changes by instant; changes of one queue at the same instant keep the order they were
/// scheduled in. A handful are pending at a time (a telegram's IDLE and REACTN edges), so
/// sorted queues beat a tree.
#[derive(Debug, Clone, Default)]
pub(crate) struct LineEvents {
    /// FIBBR and RDIST changes.
    status: VecDeque<(Instant, Change)>,
    /// IDLE and REACTN changes.
    pins: VecDeque<(Instant, Change)>,
    /// The RDIST value of the last applied change (the port's RDIST status).
    rdist_now: bool,
    /// The instants of the first entries of `status` and `pins`, kept up to date by every
    /// change of the queues: the chip asks for them on every advance, so they are loads, not
    /// queue fronts.
    fronts: (Option<Instant>, Option<Instant>),
    /// The last RDIST change in `status` (the latest), if any: what a new RDIST change is
    /// compared with (one is scheduled for every received segment).
    rdist_last: Option<(Instant, bool)>,
    /// IDLE / REACTN changes are kept in time order in `pins` (a serial-port pin is
    /// traced); otherwise in `quiet`.
    pins_loud: bool,
    /// IDLE and REACTN changes while the pins are quiet.
    quiet: QuietPins,
    /// Debug builds: `quiet` with every own telegram kept as its two changes (the general
    /// form), and its levels before them (set at the first quiet read or application), to
    /// compare the levels read with.
    #[cfg(debug_assertions)]
    shadow: (QuietPins, Option<(bool, bool)>),
}

/// Inserts `(at, change)` into the time-ordered `queue`, after the entries at `at`.
fn insert(queue: &mut VecDeque<(Instant, Change)>, at: Instant, change: Change) {
    if queue.back().is_none_or(|(t, _)| *t <= at) {
        // The usual case: changes are scheduled in time order.
        queue.push_back((at, change));
        return;
    }
    // Otherwise it belongs a few places from the back (an own telegram's IDLE edges before
    // the REACTN edges of frames already handed over): appended and moved back by swaps,
    // not a binary search and a `VecDeque::insert` (a memmove call each; pair3).
    queue.push_back((at, change));
    let mut i = queue.len().saturating_sub(1);
    while i > 0 && queue.get(i - 1).is_some_and(|(t, _)| *t > at) {
        queue.swap(i - 1, i);
        i -= 1;
    }
}

impl LineEvents {
    /// Schedules `change` at `at` (after the changes already scheduled at `at`).
    /// An RDIST change to the value RDIST already has at `at` is dropped: it would change
    /// nothing and only wake the chip (one is scheduled for every received segment).
    pub(crate) fn push(&mut self, at: Instant, change: Change) {
        if change.is_pin_level() {
            if !self.pins_loud {
                self.quiet.push(at, change);
                #[cfg(debug_assertions)]
                self.shadow.0.push(at, change);
                return;
            }
            insert(&mut self.pins, at, change);
            self.fronts.1 = Some(self.fronts.1.map_or(at, |f| f.min(at)));
            return;
        }
        if let Change::Rdist(v) = change
            && self.rdist_at_end_if_last(at) == Some(v)
        {
            return;
        }
        insert(&mut self.status, at, change);
        if let Change::Rdist(v) = change
            && self.rdist_last.is_none_or(|(t, _)| t <= at)
        {
            // Inserted after every entry at or before `at`: the last RDIST change.
            self.rdist_last = Some((at, v));
        }
        self.fronts.0 = Some(self.fronts.0.map_or(at, |f| f.min(at)));
        debug_assert_eq!(self.fronts, self.compute_fronts());
        debug_assert_eq!(self.rdist_last, self.compute_rdist_last());
    }

    /// Schedules a received telegram's REACTN pulse (410B §2 REACTN: low from `low` while
    /// the telegram is received, high again from `end`): the two changes [`LineEvents::push`]
    /// schedules for them, one after the other; quiet, kept as a pulse or appended in one
    /// go (`QuietPins::push_reactn_pulse`).
    #[inline(always)]
    pub(crate) fn push_reactn_pulse(&mut self, low: Instant, end: Instant) {
        // The usual case first: loud, no pulse is kept, so this keeps none.
        let kept = self.quiet.push_reactn_pulse_kept(low, end);
        debug_assert!(
            !(kept && self.pins_loud),
            "a pulse kept while the pins are loud"
        );
        if !kept {
            if self.pins_loud {
                self.push(low, Change::Reactn(false));
                self.push(end, Change::Reactn(true));
                return;
            }
            self.quiet.push_reactn_pulse_rest(low, end);
        }
        #[cfg(debug_assertions)]
        {
            self.shadow.0.push(low, Change::Reactn(false));
            self.shadow.0.push(end, Change::Reactn(true));
        }
    }

    /// Schedules an own telegram's IDLE changes (410B §2 IDLE: 0 from `start` while the
    /// telegram is sent, 1 from `end`); quiet, they are kept as the interval
    /// (`QuietPins::push_own`).
    pub(crate) fn push_own_idle(&mut self, start: Instant, end: Instant) {
        // The usual case first: loud, no interval is kept, so this keeps none.
        let kept = self.quiet.push_own_kept(start, end);
        debug_assert!(
            !(kept && self.pins_loud),
            "an own interval kept while the pins are loud"
        );
        if !kept {
            if self.pins_loud {
                self.push(start, Change::Idle(false));
                self.push(end, Change::Idle(true));
                return;
            }
            self.quiet.push_own(start, end);
        }
        #[cfg(debug_assertions)]
        {
            self.shadow.0.push(start, Change::Idle(false));
            self.shadow.0.push(end, Change::Idle(true));
        }
    }

    /// Debug builds: the levels read with the own intervals equal those of the general
    /// form (`shadow`); `base` is the caller's levels before the changes kept.
    #[cfg(debug_assertions)]
    fn check_quiet(&mut self, base: (bool, bool)) {
        let shadow_base = *self.shadow.1.get_or_insert(base);
        let got = (
            self.quiet.level(PinLine::Idle, base.0),
            self.quiet.level(PinLine::Reactn, base.1),
        );
        let want = (
            self.shadow.0.level(PinLine::Idle, shadow_base.0),
            self.shadow.0.level(PinLine::Reactn, shadow_base.1),
        );
        debug_assert_eq!(got, want, "quiet pin levels: own intervals against changes");
    }

    /// `rdist_last` from the queue.
    fn compute_rdist_last(&self) -> Option<(Instant, bool)> {
        self.status.iter().rev().find_map(|(t, c)| match c {
            Change::Rdist(v) => Some((*t, *v)),
            _ => None,
        })
    }

    /// `fronts` from the queues.
    fn compute_fronts(&self) -> (Option<Instant>, Option<Instant>) {
        (
            self.status.front().map(|(t, _)| *t),
            self.pins.front().map(|(t, _)| *t),
        )
    }

    /// The instant of the earliest change.
    pub(crate) fn next_at(&self) -> Option<Instant> {
        debug_assert_eq!(self.fronts, self.compute_fronts());
        earliest(self.fronts.0, self.fronts.1)
    }

    /// The instant of the earliest change to apply in time order: a status change, or any
    /// change when `pins_loud` (IDLE or REACTN traced).
    pub(crate) fn next_loud_at(&self, pins_loud: bool) -> Option<Instant> {
        debug_assert_eq!(self.fronts, self.compute_fronts());
        let status = self.fronts.0;
        if pins_loud {
            earliest(status, self.fronts.1)
        } else {
            status
        }
    }

    /// The RDIST value after every scheduled change, when no RDIST change is scheduled
    /// after `at` (`None` otherwise): an RDIST change of that value at `at` or later would be
    /// dropped (`push`).
    pub(crate) fn rdist_at_end_if_last(&self, at: Instant) -> Option<bool> {
        debug_assert_eq!(self.rdist_last, self.compute_rdist_last());
        match self.rdist_last {
            Some((t, v)) => (t <= at).then_some(v),
            None => Some(self.rdist_now),
        }
    }

    /// Removes and returns the earliest change if it is at or before `t` (status changes
    /// first at equal instants; the two kinds do not depend on each other).
    pub(crate) fn pop_until(&mut self, t: Instant) -> Option<(Instant, Change)> {
        let s = self.fronts.0.filter(|at| *at <= t);
        let p = self.fronts.1.filter(|at| *at <= t);
        let next = match (s, p) {
            (Some(a), Some(b)) if b < a => self.pop_pin(),
            (Some(_), _) => {
                let next = self.status.pop_front();
                self.fronts.0 = self.status.front().map(|(t, _)| *t);
                next
            }
            (None, Some(_)) => self.pop_pin(),
            (None, None) => None,
        };
        if let Some((_, Change::Rdist(v))) = next {
            self.rdist_now = v;
            // Popped from the front: the last one only when it was the only one.
            self.rdist_last = self.compute_rdist_last();
        }
        next
    }

    /// Removes and returns the earliest IDLE / REACTN change if it is at or before `t`.
    pub(crate) fn pop_pin_until(&mut self, t: Instant) -> Option<(Instant, Change)> {
        debug_assert_eq!(self.fronts, self.compute_fronts());
        if self.fronts.1.is_some_and(|at| at <= t) {
            self.pop_pin()
        } else {
            None
        }
    }

    /// Removes and returns the first IDLE / REACTN change.
    fn pop_pin(&mut self) -> Option<(Instant, Change)> {
        let next = self.pins.pop_front();
        self.fronts.1 = self.pins.front().map(|(t, _)| *t);
        next
    }

    /// Drops the receiver's changes at or after `t` (a collision cut the signal they came
    /// from).
    pub(crate) fn cancel_receive_from(&mut self, t: Instant) {
        self.status.retain(|(at, c)| *at < t || !c.is_receive());
        self.pins.retain(|(at, c)| *at < t || !c.is_receive());
        self.quiet.cancel_receive_from(t);
        #[cfg(debug_assertions)]
        self.shadow.0.cancel_receive_from(t);
        self.fronts = self.compute_fronts();
        self.rdist_last = self.compute_rdist_last();
    }

    /// Whether IDLE / REACTN changes are kept in time order (a serial-port pin is traced).
    pub(crate) fn pins_loud(&self) -> bool {
        self.pins_loud
    }

    /// The level of `pin` while the pins are quiet (`QuietPins::level`).
    pub(crate) fn quiet_level(&self, pin: PinLine, base: bool) -> bool {
        #[cfg(debug_assertions)]
        if let Some(b) = self.shadow.1 {
            let shadow_base = if pin == PinLine::Idle { b.0 } else { b.1 };
            debug_assert_eq!(
                self.quiet.level(pin, base),
                self.shadow.0.level(pin, shadow_base),
                "quiet pin level of {pin:?}: own intervals against changes"
            );
        }
        self.quiet.level(pin, base)
    }

    /// The instant the pin levels are applied to moves on to `t` (`QuietPins::apply`).
    pub(crate) fn apply_quiet_pins(&mut self, t: Instant, levels: &mut (bool, bool)) {
        // Loud, the levels are the port's own (applied in time order): nothing to compare.
        #[cfg(debug_assertions)]
        if !self.pins_loud {
            let mut b = *self.shadow.1.get_or_insert(*levels);
            self.shadow.0.apply(t, &mut b);
            self.shadow.1 = Some(b);
        }
        self.quiet.apply(t, levels);
        #[cfg(debug_assertions)]
        if !self.pins_loud {
            self.check_quiet(*levels);
        }
    }

    /// [`LineEvents::apply_quiet_pins`] when the pins are quiet and their list is not long
    /// enough to be folded (every advance of a chip ends with it): only the instant the
    /// changes count up to moves to `t`, the levels (`levels`, IDLE and REACTN) stand.
    /// Returns whether it applied; `false` leaves everything as it was, for the full
    /// application. Debug builds run the full application on a copy and compare.
    #[inline]
    pub(crate) fn apply_quiet_pins_unfolded(&mut self, t: Instant, levels: (bool, bool)) -> bool {
        if self.pins_loud || self.quiet.folds() {
            return false;
        }
        #[cfg(debug_assertions)]
        let full = {
            let mut full = self.quiet.clone();
            let mut l = levels;
            full.apply(t, &mut l);
            (full, l)
        };
        #[cfg(not(debug_assertions))]
        let _ = levels;
        self.quiet.apply_to(t);
        #[cfg(debug_assertions)]
        {
            let mut b = *self.shadow.1.get_or_insert(levels);
            self.shadow.0.apply(t, &mut b);
            self.shadow.1 = Some(b);
            self.check_quiet(levels);
            debug_assert!(
                full.0 == self.quiet && full.1 == levels,
                "quiet pins applied without a fold"
            );
        }
        true
    }

    /// Keeps IDLE / REACTN changes in time order from now on (`loud`) or not; `levels`
    /// (IDLE, REACTN) are then the levels as applied, with every kept change after them.
    pub(crate) fn set_pins_loud(&mut self, loud: bool, levels: &mut (bool, bool)) {
        if loud == self.pins_loud {
            return;
        }
        if loud {
            self.pins_loud = true;
            #[cfg(debug_assertions)]
            {
                let mut b = self.shadow.1.take().unwrap_or(*levels);
                drop(self.shadow.0.take_pending(&mut b));
                let mut l = *levels;
                drop(self.quiet.clone().take_pending(&mut l));
                debug_assert_eq!(l, b, "levels handed over: own intervals against changes");
            }
            // In the order they were scheduled: the queue keeps that order within an instant
            // (an own interval's two changes come last).
            for (at, change) in self.quiet.take_pending(levels) {
                self.push(at, change);
            }
        } else {
            // The queue holds only changes after the applied instant (applied in time order
            // up to it).
            self.pins_loud = false;
            #[cfg(debug_assertions)]
            {
                // Empty since `take_pending`, at the applied instant.
                self.shadow = (self.quiet.clone(), Some(*levels));
            }
            for (at, change) in self.pins.drain(..) {
                self.quiet.push(at, change);
                #[cfg(debug_assertions)]
                self.shadow.0.push(at, change);
            }
            self.fronts = self.compute_fronts();
        }
    }

    /// What the queues hold, for comparisons in debug builds and tests.
    #[cfg(any(test, debug_assertions))]
    pub(crate) fn digest(&self) -> String {
        format!("{self:?}")
    }

    /// Number of scheduled FIBBR / RDIST changes.
    pub(crate) fn status_len(&self) -> usize {
        self.status.len()
    }

    /// Takes back a FIBBR / RDIST change scheduled lately, if it is still pending (the last
    /// entry equal to it).
    pub(crate) fn unschedule_status(&mut self, entry: (Instant, Change)) {
        if let Some(i) = self.status.iter().rposition(|e| *e == entry) {
            self.status.remove(i);
            self.fronts = self.compute_fronts();
            self.rdist_last = self.compute_rdist_last();
        }
    }

    /// The last scheduled FIBBR value, if any is scheduled.
    pub(crate) fn last_fibbr(&self) -> Option<bool> {
        self.status.iter().rev().find_map(|(_, c)| match c {
            Change::Fibbr(v) => Some(*v),
            _ => None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Changes come out by instant, those of one instant in the order they were scheduled
    // (the module's contract), whatever order they were scheduled in.
    #[test]
    fn insert_keeps_time_order_and_the_order_within_an_instant() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for round in 0..200 {
            let mut q = VecDeque::new();
            let mut want: Vec<(Instant, Change)> = Vec::new();
            for k in 0..(round % 13) {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let at = Instant::from_picos(seed % 6);
                let change = Change::Reactn(k % 2 == 0);
                insert(&mut q, at, change);
                // Reference: after every entry at or before `at`.
                let idx = want.partition_point(|(t, _)| *t <= at);
                want.insert(idx, (at, change));
            }
            assert_eq!(q.iter().copied().collect::<Vec<_>>(), want, "round {round}");
        }
    }

    /// Applies the loud queue's pin changes up to `upto`, as `SerialPort::apply_pin_levels`.
    fn apply_loud(ev: &mut LineEvents, upto: Instant, levels: &mut (bool, bool)) {
        while let Some((_, change)) = ev.pop_pin_until(upto) {
            match change {
                Change::Idle(l) => levels.0 = l,
                Change::Reactn(l) => levels.1 = l,
                _ => {}
            }
        }
    }

    // The quiet pins (changes kept as scheduled, read when asked for) give the levels the
    // time-ordered queue gives, changes of one instant in the order they were scheduled
    // (410B §2 IDLE, REACTN), whatever the order of scheduling, trims, cancels (a
    // collision, `cancel_receive_from`) and switches between the two ways.
    #[test]
    fn quiet_pin_levels_follow_the_time_ordered_queue() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for round in 0..400 {
            let mut loud = LineEvents {
                pins_loud: true,
                ..LineEvents::default()
            };
            let mut quiet = LineEvents::default();
            let (mut loud_levels, mut quiet_levels) = ((true, true), (true, true));
            let mut upto = 0u64;
            let mut latest = 0u64;
            let mut own_end = 0u64;
            let mut pulse_end = 0u64;
            for step in 0..240 {
                match next() % 8 {
                    0 => {
                        // Time goes on.
                        upto += next() % 5;
                        let t = Instant::from_picos(upto);
                        apply_loud(&mut loud, t, &mut loud_levels);
                        // As the port applies them (`SerialPort::apply_pin_levels`).
                        if !quiet.apply_quiet_pins_unfolded(t, quiet_levels) {
                            quiet.apply_quiet_pins(t, &mut quiet_levels);
                        }
                    }
                    1 => {
                        // A collision cuts what the receiver scheduled.
                        let t = Instant::from_picos((upto + next() % 6).saturating_sub(2));
                        loud.cancel_receive_from(t);
                        quiet.cancel_receive_from(t);
                        if step % 2 == 0 {
                            loud.push(t, Change::Reactn(true));
                            quiet.push(t, Change::Reactn(true));
                        }
                    }
                    2 if round % 3 == 0 => {
                        // The quiet one turns loud and back (a trace switched on and off).
                        quiet.set_pins_loud(true, &mut quiet_levels);
                        quiet.set_pins_loud(false, &mut quiet_levels);
                    }
                    3 | 4 => {
                        // An own telegram (410B §2 IDLE), placed after the one before as
                        // the transmitter does, sometimes before the applied instant.
                        let start = (upto + next() % 7).saturating_sub(2).max(own_end);
                        own_end = start + next() % 6;
                        let (s, e) = (Instant::from_picos(start), Instant::from_picos(own_end));
                        loud.push_own_idle(s, e);
                        quiet.push_own_idle(s, e);
                    }
                    5 => {
                        // A received telegram's REACTN pulse (410B §2 REACTN), mostly after
                        // the one before as the receiver schedules them (ended by the
                        // applied instant or not yet: a batch), now and then not, sometimes
                        // before the applied instant.
                        let mut low = (upto + next() % 7).saturating_sub(2);
                        if next() % 4 != 0 {
                            low = low.max(pulse_end);
                        }
                        pulse_end = low + next() % 6;
                        let (l, e) = (Instant::from_picos(low), Instant::from_picos(pulse_end));
                        loud.push_reactn_pulse(l, e);
                        quiet.push_reactn_pulse(l, e);
                    }
                    _ => {
                        // Mostly ahead of the applied instant, sometimes out of order,
                        // now and then before it (a late input); in every other round in
                        // time order (as telegrams schedule them: the lists' usual case).
                        let mut at = (upto + next() % 9).saturating_sub(2);
                        if round % 2 == 1 {
                            at = at.max(latest);
                            latest = at;
                        }
                        let at = Instant::from_picos(at);
                        // In every fifth round IDLE changes come from own telegrams only.
                        let change = match next() % 4 {
                            _ if round % 5 == 4 => Change::Reactn(next() % 2 == 0),
                            0 => Change::Idle(false),
                            1 => Change::Idle(true),
                            2 => Change::Reactn(false),
                            _ => Change::Reactn(true),
                        };
                        loud.push(at, change);
                        quiet.push(at, change);
                    }
                }
                // Levels are read with the changes up to the chip's time applied (the
                // port applies them at the end of every advance and line input).
                let t = Instant::from_picos(upto);
                apply_loud(&mut loud, t, &mut loud_levels);
                let got = (
                    quiet.quiet_level(PinLine::Idle, quiet_levels.0),
                    quiet.quiet_level(PinLine::Reactn, quiet_levels.1),
                );
                assert_eq!(got, loud_levels, "round {round} step {step}");
            }
        }
    }
}
