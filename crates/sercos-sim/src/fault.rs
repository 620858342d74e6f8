//! Faults, scheduled in simulated time and seeded. A fault acts only on the line (segments)
//! or the pins and power of a node, never on a controller's internals.

use rand_chacha::ChaCha8Rng;
use rand_core::{RngCore, SeedableRng};
use sercon_model::serial_port::{LineSegment, LineSignal, Shared};
use sercos_wire::line::BitVec;
use sercos_wire::time::Instant;

/// Bits of the opening flag left alone by a burst (8 line bits).
const FLAG_BITS: u64 = 8;

/// What goes wrong.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaultKind {
    /// The fibre of `segment` breaks (dark) and is repaired at `until`, if given.
    FibreBreak {
        /// Segment (fibre) index.
        segment: usize,
        /// Repair time.
        until: Option<Instant>,
    },
    /// Bit errors at `rate` (probability per line bit) on `segment` until `until`.
    BitErrors {
        /// Segment index.
        segment: usize,
        /// End of the error period.
        until: Instant,
        /// Probability that a line bit is inverted.
        rate: f64,
    },
    /// A burst of `bits` inverted line bits in the first telegram that enters `segment` at
    /// or after the fault's time, between its flags.
    BitErrorBurst {
        /// Segment index.
        segment: usize,
        /// Length of the burst in line bits (at least 1).
        bits: u32,
    },
    /// The node is powered off, and on again at `until`, if given.
    PowerOff {
        /// Node index.
        node: usize,
        /// Power-on time.
        until: Option<Instant>,
    },
    /// From the fault's time on the node's MCLK runs with this error.
    ClockDrift {
        /// Node index.
        node: usize,
        /// New frequency error in ppm.
        ppm: f64,
    },
    /// The signal on `segment` is distorted beyond the receiver's limit until `until`
    /// (410B §4.1 2H.12 RDIST).
    Distortion {
        /// Segment index.
        segment: usize,
        /// End of the distortion.
        until: Instant,
    },
}

/// A fault at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fault {
    /// When it starts.
    pub at: Instant,
    /// What it is.
    pub kind: FaultKind,
}

/// Converts ppm to ppb (rounded; NaN gives 0).
pub fn ppm_to_ppb(ppm: f64) -> i64 {
    if ppm.is_finite() {
        (ppm * 1000.0).round().clamp(-1e15, 1e15) as i64
    } else {
        0
    }
}

/// The faults acting on one segment, with their random source.
#[derive(Debug, Clone)]
pub(crate) struct SegmentFaults {
    breaks: Vec<(Instant, Instant)>,
    errors: Vec<(Instant, Instant, f64)>,
    bursts: Vec<(Instant, u32, bool)>,
    distortions: Vec<(Instant, Instant)>,
    /// Keyed by the run's seed and the fibre; each segment's random errors and each burst's
    /// place come from a stream of their own (the segment's start, the burst's time), so that
    /// they do not depend on the order segments enter the fibre in.
    rng: ChaCha8Rng,
}

impl SegmentFaults {
    /// The faults of `segment` among `faults`, with an RNG keyed by `seed` and `segment`.
    pub(crate) fn new(faults: &[Fault], segment: usize, seed: u64) -> Self {
        let mut s = SegmentFaults {
            breaks: Vec::new(),
            errors: Vec::new(),
            bursts: Vec::new(),
            distortions: Vec::new(),
            rng: ChaCha8Rng::seed_from_u64(
                seed ^ (segment as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
            ),
        };
        for f in faults {
            match f.kind {
                FaultKind::FibreBreak { segment: k, until } if k == segment => {
                    s.breaks.push((f.at, until.unwrap_or(Instant::MAX)));
                }
                FaultKind::BitErrors {
                    segment: k,
                    until,
                    rate,
                } if k == segment => s.errors.push((f.at, until, rate)),
                FaultKind::BitErrorBurst { segment: k, bits } if k == segment => {
                    s.bursts.push((f.at, bits.max(1), false));
                }
                FaultKind::Distortion { segment: k, until } if k == segment => {
                    s.distortions.push((f.at, until));
                }
                _ => {}
            }
        }
        s.bursts.sort_by_key(|b| b.0);
        s
    }

    /// Whether nothing ever acts here.
    pub(crate) fn is_clean(&self) -> bool {
        self.breaks.is_empty()
            && self.errors.is_empty()
            && self.bursts.is_empty()
            && self.distortions.is_empty()
    }

    /// Whether the fibre is broken at `t`.
    pub(crate) fn broken_at(&self, t: Instant) -> bool {
        self.breaks.iter().any(|(a, b)| *a <= t && t < *b)
    }

    /// The segment as it leaves the fibre: distorted, or with bits inverted (then without
    /// hint, so that every receiver downstream decodes it).
    pub(crate) fn apply(&mut self, mut seg: LineSegment) -> LineSegment {
        if self.is_clean() {
            return seg;
        }
        let end = seg.end().unwrap_or(seg.start);
        if self
            .distortions
            .iter()
            .any(|(a, b)| *a <= end && seg.start < *b)
        {
            seg.distorted = true;
        }
        let LineSignal::Bits(bits) = &seg.signal else {
            return seg;
        };
        let n = bits.len();
        let mut flips: Vec<u64> = Vec::new();
        // Bursts: the first telegram at or after the burst's time takes it.
        if let Some(b) = self
            .bursts
            .iter_mut()
            .find(|b| !b.2 && b.0 <= seg.start && seg.hint.is_some())
        {
            b.2 = true;
            let offset = seg.hint.as_ref().map_or(0, |h| h.offset);
            let first = offset + FLAG_BITS;
            let last = n.saturating_sub(FLAG_BITS); // closing flag starts here
            let len = u64::from(b.1);
            if last > first {
                let room = (last - first).saturating_sub(len).max(1);
                // Where in the telegram: drawn from the burst's own stream (its time).
                self.rng.set_stream(!b.0.as_picos());
                self.rng.set_word_pos(0);
                let at = first + self.rng.next_u64() % room;
                flips.extend((at..(at + len).min(last)).collect::<Vec<_>>());
            }
        }
        // Random errors while a period lasts: drawn from a stream of the segment's own (its
        // start on this fibre), so that which bits a period breaks does not depend on the
        // order in which the simulation hands segments to the fibre (the fast path sends a
        // slave's AT on before an earlier one of a slave further on; spec-notes "Faults").
        let bt = seg.bit_time.as_picos().max(1);
        if !self.errors.is_empty() {
            self.rng.set_stream(seg.start.as_picos());
            self.rng.set_word_pos(0);
        }
        for &(a, b, rate) in &self.errors {
            if rate.is_nan() || rate <= 0.0 || b <= seg.start || a > end {
                continue;
            }
            let p = rate.min(1.0);
            for i in 0..n {
                let t = seg.start.as_picos().saturating_add(i.saturating_mul(bt));
                if t < a.as_picos() || t >= b.as_picos() {
                    continue;
                }
                // 53 random bits → uniform in [0, 1).
                let u = (self.rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
                if u < p {
                    flips.push(i);
                }
            }
        }
        if flips.is_empty() {
            return seg;
        }
        flips.sort_unstable();
        flips.dedup();
        let mut out = BitVec::with_capacity(usize::try_from(n).unwrap_or(0));
        let mut next = flips.iter().peekable();
        for (i, b) in bits.bits().iter().enumerate() {
            let i = i as u64;
            let flip = next.peek().is_some_and(|f| **f == i);
            if flip {
                next.next();
            }
            out.push(b ^ flip);
        }
        seg.signal = LineSignal::Bits(Shared::new(out));
        seg.hint = None;
        seg
    }
}
