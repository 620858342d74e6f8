//! A queue whose first entry is kept in place, in front of a `VecDeque` of the others.
//!
//! Two of the chip's queues hold one entry at a time, mostly, on a steady ring: the
//! telegram processor's received frames (a slave takes its MST before its MDT comes) and the
//! transmitter's background (a ring slave's carried MST copy, the MDT copy merged behind it,
//! both followed at its take). Their first entry is then a load, and a push onto an empty
//! queue or a pop of the only entry a write or a read of that place, without a ring
//! buffer's index arithmetic (the transmitter's `OwnQueue` found the same for its own
//! telegrams). What goes behind the first is pushed inline; what moves up when the first is
//! taken is handled out of line. In every other respect the same queue as a `VecDeque<T>` (tested against
//! one below).

use std::collections::VecDeque;

/// A `VecDeque<T>` with its first entry in place. `REST_INLINE`: what moves up from behind
/// the first is handled inline too (the transmitter's own telegrams: a master queues
/// several a cycle, measured cheaper so; the other queues hold one, mostly, and keep that
/// path out of line).
#[derive(Debug, Clone)]
pub(crate) struct FirstQueue<T, const REST_INLINE: bool = false> {
    /// The first; `None` only when `rest` is empty too.
    first: Option<T>,
    /// The ones after it.
    rest: VecDeque<T>,
}

impl<T, const REST_INLINE: bool> Default for FirstQueue<T, REST_INLINE> {
    fn default() -> Self {
        FirstQueue {
            first: None,
            rest: VecDeque::new(),
        }
    }
}

impl<T, const REST_INLINE: bool> FirstQueue<T, REST_INLINE> {
    /// The first entry.
    #[inline]
    pub(crate) fn front(&self) -> Option<&T> {
        debug_assert!(self.first.is_some() || self.rest.is_empty());
        self.first.as_ref()
    }

    /// The last entry.
    #[inline]
    pub(crate) fn back(&self) -> Option<&T> {
        self.rest.back().or(self.first.as_ref())
    }

    /// Whether nothing is queued.
    #[inline]
    pub(crate) fn is_empty(&self) -> bool {
        self.first.is_none()
    }

    /// Appends `entry`: in place when the queue is empty, the usual case (written there
    /// from the caller's registers); otherwise behind the first.
    #[inline(always)]
    pub(crate) fn push_back(&mut self, entry: T) {
        if self.first.is_none() {
            debug_assert!(self.rest.is_empty());
            self.first = Some(entry);
        } else {
            // Inline for every queue (session 30: out of line it cost the master's eight ATs
            // a call each).
            self.rest.push_back(entry);
        }
    }

    /// Removes and returns the first entry; the next one, if any, moves into its place out
    /// of line.
    #[inline(always)]
    pub(crate) fn pop_front(&mut self) -> Option<T> {
        debug_assert!(self.first.is_some() || self.rest.is_empty());
        let first = self.first.take()?;
        if !self.rest.is_empty() {
            if REST_INLINE {
                self.first = self.rest.pop_front();
            } else {
                self.move_up();
            }
        }
        Some(first)
    }

    /// The first of `rest` into the first place (left empty by [`FirstQueue::pop_front`]).
    #[cold]
    #[inline(never)]
    fn move_up(&mut self) {
        debug_assert!(self.first.is_none());
        if let Some(next) = self.rest.pop_front() {
            // The first place is empty: filled without a drop of what it held.
            self.first.get_or_insert(next);
        }
    }

    /// Removes and returns the last entry.
    pub(crate) fn pop_back(&mut self) -> Option<T> {
        if self.rest.is_empty() {
            self.first.take()
        } else {
            self.rest.pop_back()
        }
    }

    /// Puts `entry` in front of the others.
    pub(crate) fn push_front(&mut self, entry: T) {
        if let Some(old) = self.first.replace(entry) {
            self.rest.push_front(old);
        }
    }

    /// Removes every entry.
    pub(crate) fn clear(&mut self) {
        self.first = None;
        self.rest.clear();
    }

    /// Whether exactly one entry is queued.
    #[inline]
    pub(crate) fn is_single(&self) -> bool {
        self.first.is_some() && self.rest.is_empty()
    }

    /// The entries, first to last.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &T> {
        self.first.iter().chain(self.rest.iter())
    }

    /// The entries, first to last, to change.
    pub(crate) fn iter_mut(&mut self) -> impl Iterator<Item = &mut T> {
        self.first.iter_mut().chain(self.rest.iter_mut())
    }

    /// The entry at `index` (0: the first).
    pub(crate) fn get(&self, index: usize) -> Option<&T> {
        match index.checked_sub(1) {
            None => self.first.as_ref(),
            Some(i) => self.rest.get(i),
        }
    }

    /// The entry at `index` (0: the first), to change.
    pub(crate) fn get_mut(&mut self, index: usize) -> Option<&mut T> {
        match index.checked_sub(1) {
            None => self.first.as_mut(),
            Some(i) => self.rest.get_mut(i),
        }
    }

    /// Removes and returns the entry at `index`, if there is one.
    pub(crate) fn remove(&mut self, index: usize) -> Option<T> {
        match index.checked_sub(1) {
            None => self.pop_front(),
            Some(i) => self.rest.remove(i),
        }
    }

    /// Puts `entry` at `index` (at most the number of entries), the entries from there on moved
    /// back by one; past the end it is appended (where `VecDeque::insert` would panic).
    pub(crate) fn insert(&mut self, index: usize, entry: T) {
        match index.checked_sub(1) {
            None => {
                if let Some(old) = self.first.replace(entry) {
                    self.rest.push_front(old);
                }
            }
            Some(_) if self.first.is_none() => self.first = Some(entry),
            Some(i) => self.rest.insert(i.min(self.rest.len()), entry),
        }
    }

    /// The index of the first entry for which `pred` is false, the entries being
    /// partitioned by it (those for which it is true first), as `VecDeque::partition_point`.
    pub(crate) fn partition_point(&self, mut pred: impl FnMut(&T) -> bool) -> usize {
        match &self.first {
            Some(f) if pred(f) => 1 + self.rest.partition_point(pred),
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Runs `ops` on a `FirstQueue` of either form and on a `VecDeque`: every operation
    /// leaves the queue as it leaves the `VecDeque` and returns what that one returns.
    fn same_as_vecdeque<const REST_INLINE: bool>(
        ops: Vec<(u8, usize, u16)>,
    ) -> Result<(), TestCaseError> {
        let mut q = FirstQueue::<u16, REST_INLINE>::default();
        let mut v: VecDeque<u16> = VecDeque::new();
        for (op, i, x) in ops {
            match op {
                0 | 1 => {
                    q.push_back(x);
                    v.push_back(x);
                }
                2 => prop_assert_eq!(q.pop_front(), v.pop_front()),
                3 => prop_assert_eq!(q.remove(i), v.remove(i)),
                4 => {
                    let i = i.min(v.len());
                    q.insert(i, x);
                    v.insert(i, x);
                }
                5 => {
                    if let Some(e) = q.get_mut(i) {
                        *e = x;
                    }
                    if let Some(e) = v.get_mut(i) {
                        *e = x;
                    }
                }
                6 => {
                    for e in q.iter_mut() {
                        *e = e.wrapping_add(x);
                    }
                    for e in v.iter_mut() {
                        *e = e.wrapping_add(x);
                    }
                }
                8 => prop_assert_eq!(q.pop_back(), v.pop_back()),
                9 => {
                    q.push_front(x);
                    v.push_front(x);
                }
                10 => {
                    if i == 0 {
                        q.clear();
                        v.clear();
                    }
                }
                _ => {
                    // Sorted, a partition point and an insert there (`on_rx_frame`).
                    let mut s: Vec<u16> = v.iter().copied().collect();
                    s.sort_unstable();
                    v = s.iter().copied().collect();
                    q = FirstQueue::<u16, REST_INLINE>::default();
                    for e in &s {
                        q.push_back(*e);
                    }
                    let p = q.partition_point(|e| *e <= x);
                    prop_assert_eq!(p, v.partition_point(|e| *e <= x));
                    q.insert(p, x);
                    v.insert(p, x);
                }
            }
            prop_assert_eq!(q.iter().count(), v.len());
            prop_assert_eq!(q.is_single(), v.len() == 1);
            prop_assert_eq!(q.is_empty(), v.is_empty());
            prop_assert_eq!(q.front(), v.front());
            prop_assert_eq!(q.back(), v.back());
            prop_assert_eq!(q.get(i), v.get(i));
            prop_assert!(q.iter().eq(v.iter()));
        }
        Ok(())
    }

    proptest! {
        /// The queue with its rest out of line (the receive queue, the background).
        #[test]
        fn a_first_queue_is_a_vecdeque(ops in prop::collection::vec((0u8..12, 0usize..6, any::<u16>()), 0..80)) {
            same_as_vecdeque::<false>(ops)?;
        }

        /// The queue with its rest inline (the transmitter's own telegrams).
        #[test]
        fn a_first_queue_with_its_rest_inline_is_a_vecdeque(ops in prop::collection::vec((0u8..12, 0usize..6, any::<u16>()), 0..80)) {
            same_as_vecdeque::<true>(ops)?;
        }
    }
}
