//! The serial port's scheduled status changes (pins IDLE, REACTN; status bits FIBBR, RDIST),
//! kept in time order and applied when the chip's time reaches them.

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
    /// Whether the receiver scheduled this change (and a collision may cancel it).
    pub(crate) fn is_receive(self) -> bool {
        !matches!(self, Change::Idle(_))
    }
}

/// Changes by instant; changes at the same instant keep the order they were scheduled in.
/// A handful are pending at a time (a telegram's IDLE and REACTN edges), so a sorted
/// queue beats a tree.
#[derive(Debug, Clone, Default)]
pub(crate) struct LineEvents {
    queue: VecDeque<(Instant, Change)>,
    /// The RDIST value of the last applied change (the port's RDIST status).
    rdist_now: bool,
}

impl LineEvents {
    /// Schedules `change` at `at` (after the changes already scheduled at `at`).
    /// An RDIST change to the value RDIST already has at `at` is dropped: it would change
    /// nothing and only wake the chip (one is scheduled for every received segment).
    pub(crate) fn push(&mut self, at: Instant, change: Change) {
        if let Change::Rdist(v) = change
            && self.rdist_at_end_if_last(at) == Some(v)
        {
            return;
        }
        if self.queue.back().is_none_or(|(t, _)| *t <= at) {
            // The usual case: changes are scheduled in time order.
            self.queue.push_back((at, change));
            return;
        }
        let idx = self.queue.partition_point(|(t, _)| *t <= at);
        self.queue.insert(idx, (at, change));
    }

    /// The instant of the earliest change.
    pub(crate) fn next_at(&self) -> Option<Instant> {
        self.queue.front().map(|(t, _)| *t)
    }

    /// The RDIST value after every scheduled change, when no RDIST change is scheduled
    /// after `at` (`None` otherwise).
    fn rdist_at_end_if_last(&self, at: Instant) -> Option<bool> {
        for (t, c) in self.queue.iter().rev() {
            if let Change::Rdist(v) = c {
                return (*t <= at).then_some(*v);
            }
        }
        Some(self.rdist_now)
    }

    /// Removes and returns the earliest change if it is at or before `t`.
    pub(crate) fn pop_until(&mut self, t: Instant) -> Option<(Instant, Change)> {
        if self.queue.front().is_some_and(|(at, _)| *at <= t) {
            let next = self.queue.pop_front();
            if let Some((_, Change::Rdist(v))) = next {
                self.rdist_now = v;
            }
            next
        } else {
            None
        }
    }

    /// Drops the receiver's changes at or after `t` (a collision cut the signal they came
    /// from).
    pub(crate) fn cancel_receive_from(&mut self, t: Instant) {
        self.queue.retain(|(at, c)| *at < t || !c.is_receive());
    }

    /// The last scheduled FIBBR value, if any is scheduled.
    pub(crate) fn last_fibbr(&self) -> Option<bool> {
        self.queue.iter().rev().find_map(|(_, c)| match c {
            Change::Fibbr(v) => Some(*v),
            _ => None,
        })
    }
}
