//! The line interface: timed segments of light on the fibre (or levels on an RS-485 line).
//!
//! A ring simulation connects chips by handing the segments one chip sends
//! ([`crate::Chip::take_line_output`]) to the next chip ([`crate::Chip::line_input`]), shifted
//! by the fibre's delay and perhaps altered by a fault injector. It needs to know nothing of
//! the chip's internals.
//!
//! Conventions (`docs/spec-notes.md`, "Serial port"):
//!
//! * A segment carries **light levels** (`true` = light on), as a transceiver that lights the
//!   fibre when the pin is 0 (the reset meaning of POLTXD / POLRXD, 410B §4.1 1H.7, 1H.9) would
//!   make them.
//! * A segment lasts until the next segment of the same line starts. [`LineSignal::Bits`] holds
//!   one level per bit time; after its last bit the line keeps that level until the next
//!   segment. [`LineSignal::Filler`], [`LineSignal::Dark`] and [`LineSignal::Light`] are
//!   open-ended and cost nothing per bit.
//! * Segments of one line come in order of `start`. A segment that starts before the end of the
//!   previous [`LineSignal::Bits`] segment cuts it there (a collision).

use std::rc::Rc;

use sercos_wire::line::BitVec;
use sercos_wire::time::{Duration, Instant};

/// How the line interface shares a segment's bits and a hint's telegram between the sender,
/// its cache of coded frames, the receiver and a repeater's copy: a reference count without
/// atomics. A simulation runs its chips on one thread, and an atomic count costs ≈ 11 ns per
/// clone and drop against a few instructions for this one (`docs/performance.md`, "Controller
/// pair"); segments and chips are therefore neither `Send` nor `Sync`.
pub type Shared<T> = Rc<T>;

/// What the line carries during a segment.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LineSignal {
    /// Explicit light levels, one per bit time, the first bit at `start`.
    Bits(Shared<BitVec>),
    /// Idle filler: the light changes at the start of every bit time (NRZI-coded data 0s, the
    /// square wave a master keeps on the fibre between telegrams; sercos-facts, Line and
    /// framing). Also the test signal "zero bit stream" (410B §2 TM1, §4.1 2H TMODE = 5).
    Filler,
    /// No light (transmitter off or high impedance, broken fibre).
    Dark,
    /// Continuous light (test signal, 410B §2 TM0, §4.1 2H TMODE = 4 or 6).
    Light,
}

/// What a [`LineSignal::Bits`] segment decodes to, so that a receiver need not decode the bits.
///
/// Valid while the bits are untouched and the line's level before the first bit equals
/// [`LineSegment::level_before`]: then an NRZI receiver decodes exactly one telegram with a
/// valid FCS, `telegram`, whose opening flag starts at bit `offset` and whose closing flag
/// ends the segment.
///
/// A segment holds its hint behind one [`Shared`] count ([`LineSegment::hint`]): the hint is
/// the same from either level (NRZI, 410B §2 TxD), so the sender makes it once per telegram
/// and every segment of that telegram, its copies and their inversions share it.
#[derive(Debug, Clone)]
pub struct FrameHint {
    /// The telegram bytes (ADR and data, without FCS).
    pub telegram: Shared<[u8]>,
    /// The first bit of the opening flag, counted from the segment's first bit.
    pub offset: u64,
    /// The telegram's bits coded from each level before the first bit (index 0: low, 1:
    /// high; NRZI from the opposite level gives every level the other way), when the sender
    /// has them at hand: [`LineSegment::inverted`] of a segment whose bits are one of them
    /// shares the other instead of copying. A cache, not part of what the hint says (`==`
    /// ignores it).
    pub coded: Option<Codings>,
}

/// A telegram's bits coded from both levels before the first bit ([`FrameHint::coded`]),
/// with the level each leaves the line at after its last bit.
#[derive(Debug, Clone)]
pub struct Codings {
    /// Index 0: from low, 1: from high.
    bits: [Shared<BitVec>; 2],
    /// The level after the last bit of each of `bits` (its level before without bits):
    /// what a receiver keeps for the filler after the telegram (410B §4.1 1H.12, 2H.13).
    ends: [bool; 2],
}

impl Codings {
    /// The codings `[from low, from high]`.
    pub fn new(bits: [Shared<BitVec>; 2]) -> Self {
        let [low, high] = &bits;
        let ends = [level_after(low, false), level_after(high, true)];
        Codings { bits, ends }
    }

    /// The bits `[from low, from high]`.
    pub fn bits(&self) -> &[Shared<BitVec>; 2] {
        &self.bits
    }
}

/// The level `bits` leave the line at after their last bit, `before` when there is none
/// (410B §2 TxD: the line keeps its last level).
#[inline(always)]
fn level_after(bits: &BitVec, before: bool) -> bool {
    match bits.len().checked_sub(1) {
        Some(i) => usize::try_from(i)
            .ok()
            .and_then(|i| bits.bits().get(i))
            .unwrap_or(before),
        None => before,
    }
}

impl FrameHint {
    /// The bits of [`FrameHint::coded`] from the level other than `level`, when `bits` are
    /// those from `level` (the same allocation): `bits` inverted.
    #[inline(always)]
    fn inverse_of(&self, bits: &Shared<BitVec>, level: bool) -> Option<&Shared<BitVec>> {
        let [low, high] = &self.coded.as_ref()?.bits;
        let (this, other) = if level { (high, low) } else { (low, high) };
        Shared::ptr_eq(bits, this).then_some(other)
    }

    /// The level `bits` leave the line at after their last bit, when they are the coding of
    /// [`FrameHint::coded`] from `level` (the same allocation; [`LineSegment::level_after_bits`]
    /// of a segment of them, found without a look at the bits).
    #[inline(always)]
    pub(crate) fn end_level(&self, bits: &Shared<BitVec>, level: bool) -> Option<bool> {
        let c = self.coded.as_ref()?;
        let [low, high] = &c.bits;
        let [low_end, high_end] = c.ends;
        let (this, end) = if level {
            (high, high_end)
        } else {
            (low, low_end)
        };
        Shared::ptr_eq(bits, this).then_some(end)
    }
}

impl PartialEq for FrameHint {
    fn eq(&self, other: &Self) -> bool {
        self.telegram == other.telegram && self.offset == other.offset
    }
}

impl Eq for FrameHint {}

/// A timed piece of the line signal.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineSegment {
    /// When the first bit time begins.
    pub start: Instant,
    /// The duration of one bit time of the sender.
    pub bit_time: Duration,
    /// What the line carries.
    pub signal: LineSignal,
    /// The light level the sender assumed before the first bit (NRZI needs it for the first
    /// bit; the [`FrameHint`] assumes it).
    pub level_before: bool,
    /// The decoded content of [`LineSignal::Bits`], if known, shared (one count for the
    /// telegram and its coded bits: a segment is moved and cloned on every hop, `FrameHint`).
    /// A fault injector that changes the bits must set it to `None`.
    pub hint: Option<Shared<FrameHint>>,
    /// The signal is distorted beyond the receiver's limit (edges off the bit grid): set by a
    /// fault injector; a receiver reports RDIST while it lasts (410B §4.1 2H.12).
    #[doc(alias = "RDIST")]
    pub distorted: bool,
    /// After the last bit of a [`LineSignal::Bits`] segment the line carries idle filler
    /// until the next segment starts, exactly as if a [`LineSignal::Filler`] segment with
    /// the same bit time and `distorted` flag started at [`LineSegment::end`] from the last
    /// bit's level ([`LineSegment::split_filler`] makes that pair). A segment starting at
    /// [`LineSegment::end`] or earlier leaves no filler (the same as `false`). `false`: the
    /// line keeps the last bit's level. Ignored for the other signals.
    ///
    /// A chip sets it only when asked to ([`crate::Chip::set_implied_filler`]): a telegram
    /// and the filler after it then travel as one segment.
    pub then_filler: bool,
}

impl LineSegment {
    /// A steady segment (filler, dark or light) from `start` until the next segment.
    pub fn steady(
        start: Instant,
        bit_time: Duration,
        signal: LineSignal,
        level_before: bool,
    ) -> Self {
        LineSegment {
            start,
            bit_time,
            signal,
            level_before,
            hint: None,
            distorted: false,
            then_filler: false,
        }
    }

    /// A segment of explicit light levels without hint.
    pub fn bits(start: Instant, bit_time: Duration, bits: BitVec, level_before: bool) -> Self {
        LineSegment {
            start,
            bit_time,
            signal: LineSignal::Bits(Shared::new(bits)),
            level_before,
            hint: None,
            distorted: false,
            then_filler: false,
        }
    }

    /// Number of bit times of a [`LineSignal::Bits`] segment; `None` for open-ended ones.
    pub fn bit_len(&self) -> Option<u64> {
        match &self.signal {
            LineSignal::Bits(b) => Some(b.len()),
            _ => None,
        }
    }

    /// The end of the last bit of a [`LineSignal::Bits`] segment; `None` for open-ended ones.
    pub fn end(&self) -> Option<Instant> {
        self.bit_len()
            .map(|n| self.start.saturating_add(self.bit_time.saturating_mul(n)))
    }

    /// The light level of the line at instant `t` ≥ `start` as far as this segment decides it
    /// (the level of the bit time in progress at `t`; `level_before` at `start` itself).
    // Inlined at every call: with the release's second own-telegram turn
    // (`Transmitter::release_merged_then_own`) LLVM kept it out of line, which cost more
    // than that turn saves.
    #[inline(always)]
    pub fn level_at(&self, t: Instant) -> bool {
        let elapsed = t.saturating_duration_since(self.start).as_picos();
        let bt = self.bit_time.as_picos().max(1);
        // Bit times begun before t: the bit in progress at t is the last of them.
        let begun = elapsed.div_ceil(bt);
        match &self.signal {
            LineSignal::Dark => false,
            LineSignal::Light => true,
            // Every begun bit time toggles the level.
            LineSignal::Filler => self.level_before ^ (begun & 1 == 1),
            LineSignal::Bits(b) => {
                if begun == 0 {
                    return self.level_before;
                }
                let idx = usize::try_from(begun.min(b.len())).unwrap_or(usize::MAX);
                let last = match idx.checked_sub(1) {
                    Some(i) => b.bits().get(i).unwrap_or(self.level_before),
                    None => self.level_before,
                };
                if self.then_filler && begun > b.len() {
                    // The implied filler toggles at the start of each of its bit times.
                    return last ^ ((begun - b.len()) & 1 == 1);
                }
                last
            }
        }
    }

    /// The segment as the pair it stands for: the bits without `then_filler`, and the
    /// [`LineSignal::Filler`] segment that follows them when `then_filler` is set.
    pub fn split_filler(mut self) -> (LineSegment, Option<LineSegment>) {
        if !self.then_filler {
            return (self, None);
        }
        self.then_filler = false;
        let filler = match self.end() {
            Some(end) => {
                let level = self.level_at(end);
                Some(LineSegment {
                    distorted: self.distorted,
                    ..LineSegment::steady(end, self.bit_time, LineSignal::Filler, level)
                })
            }
            None => None,
        };
        (self, filler)
    }

    /// A copy of this segment without its hint (the hint's telegram is not shared): what a
    /// segment that is only followed for its levels keeps.
    pub fn without_hint(&self) -> Self {
        LineSegment {
            start: self.start,
            bit_time: self.bit_time,
            signal: self.signal.clone(),
            level_before: self.level_before,
            hint: None,
            distorted: self.distorted,
            then_filler: self.then_filler,
        }
    }

    /// The same segment `delay` later.
    pub fn delayed(mut self, delay: Duration) -> Self {
        self.start = self.start.saturating_add(delay);
        self
    }

    /// The light inverted (a transceiver of the other polarity): bits are inverted, dark and
    /// light swap, filler stays filler. NRZI decodes the same, so the hint stays valid.
    /// When the bits are one of the hint's [`FrameHint::coded`], the inverted bits are the
    /// other, shared, not copied.
    pub fn inverted(mut self) -> Self {
        self.invert();
        self
    }

    /// [`LineSegment::inverted`] in place.
    #[inline(always)]
    pub fn invert(&mut self) {
        let level = self.level_before;
        self.level_before = !level;
        match &mut self.signal {
            LineSignal::Dark => self.signal = LineSignal::Light,
            LineSignal::Light => self.signal = LineSignal::Dark,
            LineSignal::Filler => {}
            LineSignal::Bits(b) => {
                let inv = match self.hint.as_ref().and_then(|h| h.inverse_of(b, level)) {
                    Some(other) => {
                        debug_assert_eq!(**other, invert_bits(b), "a hint's other coding");
                        other.clone()
                    }
                    None => Shared::new(invert_bits(b)),
                };
                *b = inv;
            }
        }
    }

    /// The light level a [`LineSignal::Bits`] segment leaves the line at after its last
    /// bit ([`LineSegment::level_at`] its [`LineSegment::end`]): the last bit's, or
    /// `level_before` without bits; `None` for the other signals.
    #[inline(always)]
    pub(crate) fn level_after_bits(&self) -> Option<bool> {
        match &self.signal {
            LineSignal::Bits(b) => Some(level_after(b, self.level_before)),
            _ => None,
        }
    }

    /// The part of this segment from instant `t` on (`t` ≥ `start`): a steady segment starts
    /// at `t`; a bits segment keeps the bit times that begin at or after `t` (none: `None`).
    /// The hint is dropped unless nothing was cut.
    pub fn from_instant(&self, t: Instant) -> Option<LineSegment> {
        if t <= self.start {
            return Some(self.clone());
        }
        let level_before = self.level_at(t);
        match &self.signal {
            LineSignal::Bits(b) => {
                let elapsed = t.saturating_duration_since(self.start).as_picos();
                let bt = self.bit_time.as_picos().max(1);
                let skip = elapsed.div_ceil(bt);
                if skip >= b.len() {
                    // Only the implied filler is left, if any: as its own segment (from
                    // the end of the bits) would be cut at `t`.
                    return self.then_filler.then(|| {
                        let at = self.end().map_or(t, |e| e.max(t));
                        LineSegment {
                            distorted: self.distorted,
                            ..LineSegment::steady(
                                at,
                                self.bit_time,
                                LineSignal::Filler,
                                self.level_at(at),
                            )
                        }
                    });
                }
                let from = usize::try_from(skip).ok()?;
                let to = usize::try_from(b.len()).ok()?;
                let rest = b.bits().slice(from, to)?;
                let out = BitVec::from_bits(rest);
                Some(LineSegment {
                    start: self
                        .start
                        .saturating_add(self.bit_time.saturating_mul(skip)),
                    bit_time: self.bit_time,
                    signal: LineSignal::Bits(Shared::new(out)),
                    level_before,
                    hint: None,
                    distorted: self.distorted,
                    then_filler: self.then_filler,
                })
            }
            other => Some(LineSegment {
                start: t,
                bit_time: self.bit_time,
                signal: other.clone(),
                level_before,
                hint: None,
                distorted: self.distorted,
                then_filler: false,
            }),
        }
    }
}

/// The bits of `bits`, inverted.
fn invert_bits(bits: &BitVec) -> BitVec {
    bits.inverted()
}

/// Drops `seg` here, not through the drop glue's call (a ring slave's take drops the copy
/// it resumed last cycle and the line's last segment on every release; a receiver the
/// segment it kept before).
#[inline(always)]
pub(crate) fn drop_in_line(seg: LineSegment) {
    let LineSegment { signal, hint, .. } = seg;
    drop_parts_in_line(signal, hint);
}

/// [`drop_in_line`] of a segment's shared parts.
#[inline(always)]
pub(crate) fn drop_parts_in_line(signal: LineSignal, hint: Option<Shared<FrameHint>>) {
    if let LineSignal::Bits(bits) = signal {
        drop(bits);
    }
    if let Some(hint) = hint {
        drop(hint);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverting_twice_gives_the_bits_back_and_inverts_each_bit() {
        for len in [0usize, 1, 7, 8, 9, 23, 64] {
            let mut v = BitVec::new();
            for i in 0..len {
                v.push(i % 3 == 0);
            }
            let inv = invert_bits(&v);
            assert_eq!(inv.len(), v.len());
            for i in 0..len {
                assert_eq!(inv.bits().get(i), v.bits().get(i).map(|b| !b), "{len} {i}");
            }
            assert_eq!(invert_bits(&inv), v);
        }
    }

    /// A segment from each level with a hint that has both codings, and one whose bits are
    /// not the hint's own (equal, not the same allocation; or other bits).
    fn hinted(level: bool) -> (LineSegment, Shared<BitVec>, Shared<BitVec>) {
        let mut low = BitVec::new();
        for i in 0..23 {
            low.push(i % 3 == 0);
        }
        let low = Shared::new(low);
        let high = Shared::new(invert_bits(&low));
        let hint = Shared::new(FrameHint {
            telegram: Shared::from(&[1u8, 2][..]),
            offset: 0,
            coded: Some(Codings::new([low.clone(), high.clone()])),
        });
        let bits = if level { high.clone() } else { low.clone() };
        let seg = LineSegment {
            hint: Some(hint),
            ..LineSegment::steady(
                Instant::ZERO,
                Duration::from_picos(62_500),
                LineSignal::Bits(bits),
                level,
            )
        };
        (seg, low, high)
    }

    fn bits_of(seg: &LineSegment) -> &Shared<BitVec> {
        match &seg.signal {
            LineSignal::Bits(b) => b,
            _ => panic!("bits"),
        }
    }

    /// 410B §4.1 (1H.12, 2H.13: the filler after a telegram keeps the level its last bit
    /// leaves): a hint's codings know that level from either level before, the same as
    /// [`LineSegment::level_after_bits`]; bits that are not the coding from that level (the
    /// other one, or a copy) get no answer.
    #[test]
    fn a_hints_codings_know_the_level_after_their_bits() {
        for n in [0usize, 1, 2, 22, 23] {
            let mut low = BitVec::new();
            for i in 0..n {
                low.push(i % 3 == 0);
            }
            let low = Shared::new(low);
            let high = Shared::new(invert_bits(&low));
            let hint = FrameHint {
                telegram: Shared::from(&[1u8, 2][..]),
                offset: 0,
                coded: Some(Codings::new([low.clone(), high.clone()])),
            };
            for level in [false, true] {
                let (own, other) = if level { (&high, &low) } else { (&low, &high) };
                let seg = LineSegment::steady(
                    Instant::ZERO,
                    Duration::from_picos(62_500),
                    LineSignal::Bits(own.clone()),
                    level,
                );
                assert_eq!(
                    hint.end_level(own, level),
                    seg.level_after_bits(),
                    "{n} {level}"
                );
                assert_eq!(hint.end_level(other, level), None, "{n} {level}");
                let copy = Shared::new((**own).clone());
                assert_eq!(hint.end_level(&copy, level), None, "{n} {level}");
            }
        }
    }

    /// 410B §2 TxD (NRZI): inverting a segment whose bits are one of its hint's codings
    /// shares the other, from either level and back; bits that are not the hint's (the
    /// same levels in another allocation, or other levels) are inverted themselves.
    #[test]
    fn inverting_shares_the_hints_other_coding_only_for_its_own_bits() {
        for level in [false, true] {
            let (seg, low, high) = hinted(level);
            let inv = seg.clone().inverted();
            let (own, other) = if level { (&high, &low) } else { (&low, &high) };
            assert!(Shared::ptr_eq(bits_of(&seg), own));
            assert!(Shared::ptr_eq(bits_of(&inv), other), "level {level}");
            assert_eq!(inv.level_before, !level);
            let back = inv.inverted();
            assert!(Shared::ptr_eq(bits_of(&back), own), "level {level}");
            assert_eq!(back, seg);
            // The same levels, not the hint's allocation: inverted, not shared.
            let mut copy = seg.clone();
            copy.signal = LineSignal::Bits(Shared::new((**own).clone()));
            let inv = copy.inverted();
            assert!(!Shared::ptr_eq(bits_of(&inv), other));
            assert_eq!(**bits_of(&inv), **other);
            // Other levels under the same hint (a fault injector that kept it): their own
            // inversion.
            let mut changed = (**own).clone();
            changed.push(true);
            let mut seg = seg.clone();
            seg.signal = LineSignal::Bits(Shared::new(changed.clone()));
            assert_eq!(**bits_of(&seg.inverted()), invert_bits(&changed));
        }
    }
}
