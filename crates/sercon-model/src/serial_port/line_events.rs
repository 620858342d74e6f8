//! The serial port's scheduled status changes (pins IDLE, REACTN; status bits FIBBR, RDIST),
//! kept in time order and applied when the chip's time reaches them.

use std::collections::BTreeMap;

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
#[derive(Debug, Clone, Default)]
pub(crate) struct LineEvents {
    map: BTreeMap<(Instant, u64), Change>,
    seq: u64,
}

impl LineEvents {
    /// Schedules `change` at `at`.
    pub(crate) fn push(&mut self, at: Instant, change: Change) {
        self.seq = self.seq.wrapping_add(1);
        self.map.insert((at, self.seq), change);
    }

    /// The instant of the earliest change.
    pub(crate) fn next_at(&self) -> Option<Instant> {
        self.map.keys().next().map(|(t, _)| *t)
    }

    /// Removes and returns the earliest change if it is at or before `t`.
    pub(crate) fn pop_until(&mut self, t: Instant) -> Option<(Instant, Change)> {
        let (&(at, seq), _) = self.map.iter().next()?;
        if at > t {
            return None;
        }
        self.map.remove(&(at, seq)).map(|c| (at, c))
    }

    /// Drops the receiver's changes at or after `t` (a collision cut the signal they came
    /// from).
    pub(crate) fn cancel_receive_from(&mut self, t: Instant) {
        self.map.retain(|(at, _), c| *at < t || !c.is_receive());
    }

    /// The last scheduled FIBBR value, if any is scheduled.
    pub(crate) fn last_fibbr(&self) -> Option<bool> {
        self.map.values().rev().find_map(|c| match c {
            Change::Fibbr(v) => Some(*v),
            _ => None,
        })
    }
}
