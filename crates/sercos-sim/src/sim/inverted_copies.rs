//! Inverted copies of telegrams' bits, made once per telegram and shared.
//!
//! On the fast path a receiver takes a telegram from the level it is at (NRZI decodes an
//! inverted telegram the same, 410B §1: the slaves regenerate the signal), so a telegram
//! that reaches several receivers at the other level was inverted once per receiver, each
//! time into a fresh bit vector. The copies are kept here by the telegram's bits (the same
//! shared vector reaches every receiver), so each telegram is inverted once.

use sercon_model::serial_port::{LineSegment, LineSignal, Shared};
use sercos_wire::line::BitVec;

/// Telegrams whose inverted copy is kept (the newest; a cycle's telegrams reach their
/// receivers within a few events, so a handful suffices).
const KEPT: usize = 8;

/// Inverted copies of the newest telegrams' bits.
#[derive(Debug, Default)]
pub(super) struct InvertedCopies {
    /// (bits, the same bits inverted). Holding `bits` keeps its allocation alive, so no
    /// other vector can take its address while it is a key.
    kept: Vec<(Shared<BitVec>, Shared<BitVec>)>,
    /// The slot the next new copy replaces once `kept` is full.
    next: usize,
}

impl InvertedCopies {
    /// `seg` with its light inverted, as [`LineSegment::inverted`] gives it, the inverted
    /// bits shared with earlier copies of the same telegram.
    pub(super) fn invert(&mut self, seg: LineSegment) -> LineSegment {
        let LineSignal::Bits(bits) = &seg.signal else {
            return seg.inverted();
        };
        if let Some((_, inv)) = self.kept.iter().find(|(b, _)| Shared::ptr_eq(b, bits)) {
            let inv = inv.clone();
            return LineSegment {
                level_before: !seg.level_before,
                signal: LineSignal::Bits(inv),
                ..seg
            };
        }
        let bits = bits.clone();
        let out = seg.inverted();
        if let LineSignal::Bits(inv) = &out.signal {
            let entry = (bits, inv.clone());
            if self.kept.len() < KEPT {
                self.kept.push(entry);
            } else if let Some(slot) = self.kept.get_mut(self.next) {
                *slot = entry;
            }
            self.next = (self.next + 1) % KEPT;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sercos_wire::time::{Duration, Instant};

    fn telegram(seed: u64, len: usize) -> LineSegment {
        let mut v = BitVec::new();
        for i in 0..len {
            v.push((seed >> (i % 64)) & 1 == 1 || i % 5 == 0);
        }
        LineSegment::bits(
            Instant::from_picos(seed),
            Duration::from_picos(62_500),
            v,
            seed % 2 == 0,
        )
    }

    /// A kept copy equals a fresh inversion, for the same telegram delivered again, after
    /// more telegrams than are kept, and for steady signals.
    #[test]
    fn copies_equal_fresh_inversions_and_are_shared() {
        let mut copies = InvertedCopies::default();
        let segs: Vec<LineSegment> = (0..20)
            .map(|k| telegram(k * 7919 + 3, 40 + k as usize))
            .collect();
        for round in 0..3 {
            for (k, s) in segs.iter().enumerate() {
                let a = copies.invert(s.clone());
                assert_eq!(a, s.clone().inverted(), "round {round} telegram {k}");
                let b = copies.invert(s.clone());
                assert_eq!(b, a);
                if let (LineSignal::Bits(x), LineSignal::Bits(y)) = (&a.signal, &b.signal) {
                    assert!(Shared::ptr_eq(x, y), "the second copy is shared");
                }
            }
        }
        for signal in [LineSignal::Filler, LineSignal::Dark, LineSignal::Light] {
            let s = LineSegment::steady(Instant::ZERO, Duration::from_picos(62_500), signal, true);
            assert_eq!(copies.invert(s.clone()), s.inverted());
        }
    }
}
