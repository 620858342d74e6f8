//! A bump allocator over the dual-port RAM that records every structure it places and the
//! words to write.

use super::{Region, RegionKind};

/// Places structures one after another from the first free word and collects their words.
/// Addresses are kept as `u32` until the whole layout is known to fit the RAM.
#[derive(Debug, Default)]
pub(crate) struct Allocator {
    next: u32,
    pub(crate) regions: Vec<Region>,
    pub(crate) writes: Vec<(u32, u16)>,
}

impl Allocator {
    /// An allocator whose first free word is `first_free`.
    pub(crate) fn starting_at(first_free: u32) -> Self {
        Allocator {
            next: first_free,
            ..Allocator::default()
        }
    }

    /// Words used so far, counting from address 0.
    pub(crate) fn used(&self) -> u32 {
        self.next
    }

    /// Reserves `words` words for a structure of `kind` and returns its address.
    pub(crate) fn place(&mut self, kind: RegionKind, words: u32) -> u32 {
        let start = self.next;
        self.next = self.next.saturating_add(words);
        self.regions.push(Region { start, words, kind });
        start
    }

    /// Reserves and writes `words` as one structure.
    pub(crate) fn place_words(&mut self, kind: RegionKind, words: &[u16]) -> u32 {
        let len = u32::try_from(words.len()).unwrap_or(u32::MAX);
        let start = self.place(kind, len);
        self.write_words(start, words);
        start
    }

    /// Writes `words` from `start` on (inside a region already placed).
    pub(crate) fn write_words(&mut self, start: u32, words: &[u16]) {
        for (address, &word) in (start..).zip(words) {
            self.writes.push((address, word));
        }
    }

    /// Writes `count` zero words from `start` on.
    pub(crate) fn zero(&mut self, start: u32, count: u32) {
        for address in start..start.saturating_add(count) {
            self.writes.push((address, 0));
        }
    }
}
