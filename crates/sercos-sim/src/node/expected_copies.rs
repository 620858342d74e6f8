//! The forwarded segments the simulation already carried down the ring, in the order the
//! node's transmitter will release them (410B §1: "The slaves regenerate and repeat their
//! received data"): a first-in first-out list kept in one vector with a read position, so
//! that the starts are one contiguous slice when a node's next wake is computed (several
//! times per delivery), and taking the front costs an increment.

use sercos_wire::time::Instant;

/// Read position past which the taken entries are dropped from the vector.
const COMPACT_AT: usize = 64;

/// Expected forwarded segments: (local start at the output, originating node), oldest first.
#[derive(Debug, Clone, Default)]
pub(crate) struct ExpectedCopies {
    starts: Vec<Instant>,
    origins: Vec<usize>,
    /// Entries before `head` are taken.
    head: usize,
}

impl ExpectedCopies {
    /// Adds a copy expected at `start` from `origin` (after every one already listed).
    pub(crate) fn push_back(&mut self, start: Instant, origin: usize) {
        if self.head >= COMPACT_AT && 2 * self.head >= self.starts.len() {
            self.starts.drain(..self.head);
            self.origins.drain(..self.head);
            self.head = 0;
        }
        self.starts.push(start);
        self.origins.push(origin);
    }

    /// The oldest entry not yet taken.
    pub(crate) fn front(&self) -> Option<(Instant, usize)> {
        Some((*self.starts.get(self.head)?, *self.origins.get(self.head)?))
    }

    /// Takes the oldest entry.
    pub(crate) fn pop_front(&mut self) {
        if self.head < self.starts.len() {
            self.head += 1;
        }
        if self.head == self.starts.len() {
            self.clear();
        }
    }

    /// Forgets every entry.
    pub(crate) fn clear(&mut self) {
        self.starts.clear();
        self.origins.clear();
        self.head = 0;
    }

    /// The starts of the entries not yet taken, oldest first.
    pub(crate) fn starts(&self) -> &[Instant] {
        self.starts.get(self.head..).unwrap_or(&[])
    }
}

#[cfg(test)]
mod tests {
    use std::collections::VecDeque;

    use super::*;

    /// The list behaves as the double-ended queue it replaces, through compactions.
    #[test]
    fn same_as_a_deque() {
        let mut list = ExpectedCopies::default();
        let mut deque: VecDeque<(Instant, usize)> = VecDeque::new();
        let mut x: u64 = 12_345;
        for step in 0..5000u64 {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            match (x >> 33) % 7 {
                0..=2 => {
                    let e = (Instant::from_picos(step), (x >> 40) as usize % 9);
                    list.push_back(e.0, e.1);
                    deque.push_back(e);
                }
                3..=5 => {
                    list.pop_front();
                    deque.pop_front();
                }
                _ if (x >> 50) % 50 == 0 => {
                    list.clear();
                    deque.clear();
                }
                _ => {}
            }
            assert_eq!(list.front(), deque.front().copied(), "step {step}");
            let starts: Vec<Instant> = deque.iter().map(|e| e.0).collect();
            assert_eq!(list.starts(), starts.as_slice(), "step {step}");
        }
    }
}
