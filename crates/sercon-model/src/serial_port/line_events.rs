//! The serial port's scheduled status changes (pins IDLE, REACTN; status bits FIBBR, RDIST),
//! kept in time order and applied when the chip's time reaches them.
//!
//! Two queues: the status bits (FIBBR, RDIST raise interrupts and drive L_ERRN, so the chip
//! applies them in time order with its other events) and the pin levels (IDLE, REACTN,
//! which nothing else depends on: unless those pins are traced, the chip applies them in
//! bulk when its time has passed them, without an event-loop turn each).

use std::collections::VecDeque;

use sercos_wire::time::Instant;

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
        self.fronts.0 = Some(self.fronts.0.map_or(at, |f| f.min(at)));
        debug_assert_eq!(self.fronts, self.compute_fronts());
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
    /// after `at` (`None` otherwise).
    fn rdist_at_end_if_last(&self, at: Instant) -> Option<bool> {
        for (t, c) in self.status.iter().rev() {
            if let Change::Rdist(v) = c {
                return (*t <= at).then_some(*v);
            }
        }
        Some(self.rdist_now)
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
        self.fronts = self.compute_fronts();
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

/// The earlier of two optional instants.
fn earliest(a: Option<Instant>, b: Option<Instant>) -> Option<Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
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
}
